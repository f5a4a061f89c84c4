// Per-face storage left unconstructed until a face is prepared: the search's per-state tables of prepared
// faces (certificates, triangles), written by the threads that prepare them.
#pragma once

#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

namespace contactnn::contact {

/// Room for one T per face, none constructed. A std::vector's resize constructs every slot on one thread
/// before the parallel loop that prepares the faces overwrites them (29 MB of bilinear certificates a state
/// for 1e5 faces, each page first touched serially); here each slot is constructed where it is prepared, by
/// the thread that prepares it, and a slot never prepared is never touched. T must be trivially destructible
/// (the slots are never destroyed). Reading a slot that was not constructed is the caller's error.
template <class T>
class FaceSlots {
  static_assert(std::is_trivially_destructible_v<T>, "the slots are never destroyed");

 public:
  FaceSlots() = default;
  explicit FaceSlots(std::size_t faces) { reset(faces); }

  /// Room for `faces` slots, none constructed: the storage kept where it is large enough (a searcher's tables
  /// kept between states allocate nothing once warm).
  void reset(std::size_t faces) {
    if (faces > capacity_) {
      storage_.reset(new std::byte[faces * sizeof(T)]);
      capacity_ = faces;
    }
    size_ = faces;
  }

  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] std::size_t size() const { return size_; }

  /// Slot f, constructed afresh (T's default), for the caller to fill.
  T& construct(std::size_t f) { return *::new (address(f)) T(); }
  /// Slot f's storage, for the caller to construct a T in (placement new).
  [[nodiscard]] void* room(std::size_t f) const { return address(f); }
  /// Slot f, as constructed. The same, const, for readers.
  [[nodiscard]] T& operator[](std::size_t f) { return *std::launder(reinterpret_cast<T*>(address(f))); }
  [[nodiscard]] const T& operator[](std::size_t f) const {
    return *std::launder(reinterpret_cast<const T*>(address(f)));
  }

 private:
  [[nodiscard]] std::byte* address(std::size_t f) const { return storage_.get() + f * sizeof(T); }

  std::size_t size_ = 0, capacity_ = 0;
  std::unique_ptr<std::byte[]> storage_;
};

}  // namespace contactnn::contact
