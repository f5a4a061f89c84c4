// An enum's names, written once as a table (the names in the order of the enum's values 0, 1, 2, ...) and
// read both ways: the name of a value (to_string) and the value of a name (the *_from_string readers).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

namespace contactnn {

/// The name of `value` in `names`; `otherwise` for a value outside the table.
template <class Enum, std::size_t N>
[[nodiscard]] constexpr std::string_view enum_name(const std::array<std::string_view, N>& names, Enum value,
                                                   std::string_view otherwise) {
  const auto i = static_cast<std::size_t>(value);
  return i < N ? names[i] : otherwise;
}

/// The value whose name in `names` is `name`; std::nullopt for any other name.
template <class Enum, std::size_t N>
[[nodiscard]] constexpr std::optional<Enum> enum_from_name(const std::array<std::string_view, N>& names,
                                                           std::string_view name) {
  for (std::size_t i = 0; i < N; ++i) {
    if (names[i] == name) return static_cast<Enum>(i);
  }
  return std::nullopt;
}

}  // namespace contactnn
