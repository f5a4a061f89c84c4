#include "mpi/distributed_contact_search.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/conventions.hpp"
#include "core/error.hpp"
#include "geometry/surface_point.hpp"

namespace contactnn::mpi {

using geometry::Vec3;

namespace {

using contact::face_node_count;

/// The kind of error a rank found: none, or the exception to throw on every rank.
enum class ErrorKind : int { kNone = 0, kInvalidArgument = 1, kNumerical = 2, kOther = 3 };

struct LocalError {
  ErrorKind kind = ErrorKind::kNone;
  std::string message;
};

/// Runs `work`, catching what it throws into a LocalError (the first error only).
template <class F>
void capture_error(LocalError& error, F&& work) {
  if (error.kind != ErrorKind::kNone) return;
  try {
    work();
  } catch (const InvalidArgument& e) {
    error = {ErrorKind::kInvalidArgument, e.what()};
  } catch (const NumericalError& e) {
    error = {ErrorKind::kNumerical, e.what()};
  } catch (const std::exception& e) {
    error = {ErrorKind::kOther, e.what()};
  }
}

void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  throw Error(std::string("contact search under MPI: ") + what +
              " failed: " + std::string(text, static_cast<std::size_t>(length)));
}

/// MPI_Allreduce, counted.
void allreduce(const void* in, void* out, int count, MPI_Datatype type, MPI_Op op, MPI_Comm comm,
               ExchangeCounts& counts, const char* what) {
  ++counts.collectives;
  ++counts.allreduces;
  check_mpi(MPI_Allreduce(in, out, count, type, op, comm), what);
}

/// Collective: every rank learns whether any rank failed; if so, every rank throws the same exception, the
/// lowest failing rank's, its message prefixed by that rank.
void agree(MPI_Comm comm, const LocalError& error, ExchangeCounts& counts) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  const int mine = error.kind == ErrorKind::kNone ? size : rank;
  int first = size;
  allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm, counts, "MPI_Allreduce (errors)");
  if (first == size) return;
  std::array<int, 2> head{static_cast<int>(error.kind), static_cast<int>(error.message.size())};
  check_mpi(MPI_Bcast(head.data(), 2, MPI_INT, first, comm), "MPI_Bcast (error)");
  std::string message = error.message;
  message.resize(static_cast<std::size_t>(head[1]));
  check_mpi(MPI_Bcast(message.data(), head[1], MPI_CHAR, first, comm), "MPI_Bcast (error message)");
  message = "rank " + std::to_string(first) + ": " + message;
  switch (static_cast<ErrorKind>(head[0])) {
    case ErrorKind::kInvalidArgument: throw InvalidArgument(message);
    case ErrorKind::kNumerical: throw NumericalError(message);
    default: throw Error(message);
  }
}

/// The rank that checks a global id: id mod P (non-negative).
int home_of(long id, int size) { return static_cast<int>(((id % size) + size) % size); }

/// The movement budget: faces are chosen within the capture distance plus this fraction of it, and chosen
/// again only when the nodes have moved that far (one MPI_Allreduce per update otherwise).
constexpr double kBudget = 0.25;

/// MPI_Alltoallv of plain values, one vector per destination, after an MPI_Alltoall of their sizes; returns
/// one vector per source and counts what went to other ranks.
template <class T>
std::vector<std::vector<T>> exchange(MPI_Comm comm, const std::vector<std::vector<T>>& out,
                                     ExchangeCounts& counts) {
  const auto size = static_cast<int>(out.size());
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  bool too_big = false;
  std::vector<int> send_counts(static_cast<std::size_t>(size)), recv_counts(static_cast<std::size_t>(size));
  std::vector<int> send_offsets(static_cast<std::size_t>(size) + 1, 0),
      recv_offsets(static_cast<std::size_t>(size) + 1, 0);
  for (int r = 0; r < size; ++r) {
    const auto u = static_cast<std::size_t>(r);
    const std::size_t b = out[u].size() * sizeof(T);
    if (b > static_cast<std::size_t>(std::numeric_limits<int>::max())) too_big = true;
    send_counts[u] = static_cast<int>(std::min<std::size_t>(b, std::numeric_limits<int>::max()));
    if (r != rank) {
      counts.bytes_sent += static_cast<long>(b);
      counts.messages_sent += b > 0 ? 1 : 0;
      counts.header_bytes_sent += static_cast<long>(sizeof(int));
    }
  }
  counts.collectives += 2;
  // A message beyond an int's count fails every rank (a count of -1 to all of them), not the sender alone.
  if (too_big) std::fill(send_counts.begin(), send_counts.end(), -1);
  check_mpi(MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm),
            "MPI_Alltoall");
  CONTACTNN_REQUIRE(
      !too_big && std::all_of(recv_counts.begin(), recv_counts.end(), [](int c) { return c >= 0; }),
      "contact search under MPI: a rank's message to another holds more than 2^31 - 1 bytes");
  std::vector<char> send, recv;
  for (int r = 0; r < size; ++r) {
    const auto u = static_cast<std::size_t>(r);
    send_offsets[u + 1] = send_offsets[u] + send_counts[u];
    recv_offsets[u + 1] = recv_offsets[u] + recv_counts[u];
  }
  send.resize(static_cast<std::size_t>(send_offsets.back()));
  recv.resize(static_cast<std::size_t>(recv_offsets.back()));
  for (int r = 0; r < size; ++r) {
    const auto u = static_cast<std::size_t>(r);
    if (!out[u].empty())
      std::memcpy(send.data() + send_offsets[u], out[u].data(), static_cast<std::size_t>(send_counts[u]));
  }
  check_mpi(MPI_Alltoallv(send.data(), send_counts.data(), send_offsets.data(), MPI_BYTE, recv.data(),
                          recv_counts.data(), recv_offsets.data(), MPI_BYTE, comm),
            "MPI_Alltoallv");
  std::vector<std::vector<T>> in(static_cast<std::size_t>(size));
  for (int r = 0; r < size; ++r) {
    const auto u = static_cast<std::size_t>(r);
    in[u].resize(static_cast<std::size_t>(recv_counts[u]) / sizeof(T));
    if (recv_counts[u] > 0)
      std::memcpy(in[u].data(), recv.data() + recv_offsets[u], static_cast<std::size_t>(recv_counts[u]));
  }
  return in;
}

/// An interface node's copy as its home rank receives it.
struct NodeCopy {
  long id;
  double x[3];
};

/// The largest distance between two corners of a face (contact::capture_distance's face size).
double face_size(std::span<const Vec3> corners) {
  double largest = 0.0;
  for (const Vec3& a : corners)
    for (const Vec3& b : corners) largest = std::max(largest, (a - b).norm());
  return largest;
}

/// A box bounding the face's surface: its corners' box widened by the quadratic bulge. A quad8 (serendipity)
/// or tri6 face is the bilinear (linear) surface of its corners plus, per edge, the mid-side node's offset
/// from the edge's midpoint times a shape function within [0, 1]: the sum of the offsets' lengths bounds it.
std::array<double, 6> face_box(mesh::FaceType type, std::span<const Vec3> x) {
  const int corners = type == mesh::FaceType::kQuad4 || type == mesh::FaceType::kQuad8 ? 4 : 3;
  double bulge = 0.0;
  if (static_cast<int>(x.size()) > corners) {
    for (int e = 0; e < corners; ++e) {
      const Vec3 mid =
          0.5 * (x[static_cast<std::size_t>(e)] + x[static_cast<std::size_t>((e + 1) % corners)]);
      bulge += (x[static_cast<std::size_t>(corners + e)] - mid).norm();
    }
  }
  std::array<double, 6> box{};
  for (int k = 0; k < 3; ++k) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int c = 0; c < corners; ++c) {
      lo = std::min(lo, x[static_cast<std::size_t>(c)][k]);
      hi = std::max(hi, x[static_cast<std::size_t>(c)][k]);
    }
    box[static_cast<std::size_t>(k)] = lo - bulge;
    box[static_cast<std::size_t>(k) + 3] = hi + bulge;
  }
  return box;
}

bool boxes_meet(const std::array<double, 6>& a, const double* b, double reach) {
  for (std::size_t k = 0; k < 3; ++k) {
    if (a[k] > b[k + 3] + reach || b[k] - reach > a[k + 3]) return false;
  }
  return true;
}

/// A face of the local search: its global id, the rank that passed it, its type and global node ids.
struct LocalFace {
  long id;
  int owner;
  mesh::FaceType type;
  std::array<long, 8> nodes;
};

/// The box of a rank's slave nodes (empty: +inf lows, -inf highs).
std::array<double, 6> slave_box(std::span<const int> slaves, const std::function<Vec3(int)>& node_at) {
  std::array<double, 6> box{};
  for (std::size_t k = 0; k < 3; ++k) {
    box[k] = std::numeric_limits<double>::infinity();
    box[k + 3] = -std::numeric_limits<double>::infinity();
  }
  for (int s : slaves) {
    const Vec3 y = node_at(s);
    for (std::size_t k = 0; k < 3; ++k) {
      box[k] = std::min(box[k], y[static_cast<Eigen::Index>(k)]);
      box[k + 3] = std::max(box[k + 3], y[static_cast<Eigen::Index>(k)]);
    }
  }
  return box;
}

/// The local search's answers for a rank's slave nodes, before they are written to the caller's arrays.
using contact::ContactAnswers;

/// Sorts `v` and removes repeats.
template <class T, class Less = std::less<>>
void sort_unique(std::vector<T>& v, Less less = {}) {
  std::sort(v.begin(), v.end(), less);
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

struct DistributedContactSearch::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0;
  int size = 1;
  contact::ContactSearchOptions options;
  std::vector<long> face_ids;
  std::vector<mesh::FaceType> face_types;
  std::vector<long> face_offsets;  ///< face f's node ids: connectivity[face_offsets[f] ..]
  std::vector<long> connectivity;
  std::vector<int> face_nodes;  ///< coordinate-array index of each connectivity entry
  std::vector<long> node_ids;
  std::unordered_map<long, int> by_id;  ///< coordinate-array index of each node id
  std::vector<int> slave_nodes;         ///< coordinate-array index of each slave node
  std::vector<long> slave_ids;
  std::vector<int> interface_nodes;  ///< coordinate-array indices of the nodes other ranks also use
  std::vector<char> used;            ///< node i used by a face or a slave node
  ExchangeCounts counts;

  // The last exchange of faces (the ghost layer), kept while the movement since fits in its reach.
  bool track = true;  ///< options.tracking: keep the ghost layer while the movement allows
  bool exchanged = false;
  double reach = 0.0;                        ///< the reach the faces were chosen with
  std::vector<Vec3> reference;               ///< each used node's coordinates at the exchange
  std::vector<std::vector<int>> send_nodes;  ///< per rank: own nodes whose coordinates it needs, by global id
  std::vector<std::vector<int>>
      recv_slots;  ///< per rank: the local handle's node of each coordinate it sends
  std::vector<std::pair<int, int>> own_slots;  ///< (coordinate-array index, local handle's node)
  std::vector<long> local_ids;                 ///< the local handle's node ids, increasing
  std::vector<mesh::FaceType> local_types;     ///< the local handle's faces, in increasing global id
  std::vector<long> local_connectivity;
  std::vector<long> local_face_id;
  std::vector<int> local_face_owner;
  std::unique_ptr<contact::ContactSearch> handle;  ///< over the local faces; null without faces or slaves
  double handle_capture = 0.0;

  // The current update's coordinates (the caller's array).
  std::span<const double> coordinates;
  [[nodiscard]] Vec3 node_at(int i) const {
    const auto u = 3 * static_cast<std::size_t>(i);
    return {coordinates[u], coordinates[u + 1], coordinates[u + 2]};
  }

  ~Impl() {
    if (comm != MPI_COMM_NULL) MPI_Comm_free(&comm);
  }

  // Creation.
  void check_options() const;
  void index_nodes(std::span<const long> ids);
  void index_faces(std::span<const long> ids, std::span<const mesh::FaceType> types,
                   std::span<const long> nodes);
  void index_slaves(std::span<const long> slaves);
  void find_interface_nodes(ExchangeCounts& c);

  // An update.
  void check_update(const DistributedResults& out) const;
  void compare_interface_copies(LocalError& error, ExchangeCounts& c);
  std::array<double, 3> sizes_and_movement(std::vector<std::array<double, 6>>& boxes) const;
  void choose_ghost_faces(const std::vector<std::array<double, 6>>& boxes, ExchangeCounts& c);
  void adopt_local_faces(std::vector<LocalFace> kept, std::vector<std::vector<int>> send,
                         std::vector<std::vector<long>> recv_ids);
  std::vector<std::vector<double>> exchange_ghost_coordinates(ExchangeCounts& c) const;
  void search_locally(double capture, const std::vector<std::vector<double>>& xyz_in, ContactAnswers& a);
  void write_answers(const ContactAnswers& a, const DistributedResults& out) const;
};

void DistributedContactSearch::Impl::check_options() const {
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, options.quad4 == SurfaceKind::kBilinear,
      "contact search under MPI: only bilinear quad4 faces (Gregory patches need each face's "
      "ring of neighbours on the slave node's rank: not implemented)");
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, std::isfinite(options.capture_distance),
      "contact search under MPI: capture distance " << options.capture_distance << " is not finite");
}

void DistributedContactSearch::Impl::index_nodes(std::span<const long> ids) {
  CONTACTNN_REQUIRE_AS(InvalidArgument,
                       ids.size() <= static_cast<std::size_t>(std::numeric_limits<int>::max()),
                       "contact search under MPI: " << ids.size() << " nodes, at most 2^31 - 1");
  by_id.reserve(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const auto [at, inserted] = by_id.emplace(ids[i], static_cast<int>(i));
    CONTACTNN_REQUIRE_AS(InvalidArgument, inserted,
                         "contact search under MPI: node id " << ids[i] << " given twice (nodes "
                                                              << at->second << " and " << i
                                                              << " of the coordinate array)");
  }
  used.assign(ids.size(), 0);
}

void DistributedContactSearch::Impl::index_faces(std::span<const long> ids,
                                                 std::span<const mesh::FaceType> types,
                                                 std::span<const long> nodes) {
  CONTACTNN_REQUIRE_AS(
      InvalidArgument, ids.size() == types.size(),
      "contact search under MPI: " << ids.size() << " face ids for " << types.size() << " face types");
  std::size_t total = 0;
  for (std::size_t f = 0; f < types.size(); ++f) {
    const int k = face_node_count(types[f]);
    CONTACTNN_REQUIRE_AS(InvalidArgument, k > 0,
                         "contact search under MPI: face id " << ids[f] << " has type "
                                                              << static_cast<int>(types[f])
                                                              << ", expected quad4, quad8, tri3 or tri6");
    face_offsets.push_back(static_cast<long>(total));
    total += static_cast<std::size_t>(k);
  }
  face_offsets.push_back(static_cast<long>(total));
  CONTACTNN_REQUIRE_AS(InvalidArgument, nodes.size() == total,
                       "contact search under MPI: connectivity of " << nodes.size() << " node ids, the "
                                                                    << types.size() << " faces' types need "
                                                                    << total);
  for (std::size_t f = 0; f < types.size(); ++f) {
    const auto first = static_cast<std::size_t>(face_offsets[f]);
    const int k = face_node_count(types[f]);
    for (int j = 0; j < k; ++j) {
      const long id = nodes[first + static_cast<std::size_t>(j)];
      const auto at = by_id.find(id);
      CONTACTNN_REQUIRE_AS(InvalidArgument, at != by_id.end(),
                           "contact search under MPI: face id "
                               << ids[f] << " (node " << j + 1 << ") names node " << id
                               << ", whose coordinates this rank does not "
                                  "pass (a rank passes every node of its faces)");
      for (int q = 0; q < j; ++q) {
        CONTACTNN_REQUIRE_AS(InvalidArgument, nodes[first + static_cast<std::size_t>(q)] != id,
                             "contact search under MPI: face id " << ids[f] << " names node " << id
                                                                  << " twice (its nodes " << q + 1 << " and "
                                                                  << j + 1 << ")");
      }
      face_nodes.push_back(at->second);
      used[static_cast<std::size_t>(at->second)] = 1;
    }
  }
}

void DistributedContactSearch::Impl::index_slaves(std::span<const long> slaves) {
  for (std::size_t i = 0; i < slaves.size(); ++i) {
    const auto at = by_id.find(slaves[i]);
    CONTACTNN_REQUIRE_AS(InvalidArgument, at != by_id.end(),
                         "contact search under MPI: slave node "
                             << i << " names node " << slaves[i]
                             << ", whose coordinates this rank does not pass");
    slave_nodes.push_back(at->second);
    used[static_cast<std::size_t>(at->second)] = 1;
  }
}

// Global ids: face ids given twice over the ranks, and the nodes used on more than one rank. Each id goes to
// its home rank (id mod P), which answers each sender with the sender's node ids that other ranks also use.
void DistributedContactSearch::Impl::find_interface_nodes(ExchangeCounts& c) {
  const auto p = static_cast<std::size_t>(size);
  std::vector<std::vector<long>> faces_out(p), nodes_out(p);
  for (long id : face_ids) faces_out[static_cast<std::size_t>(home_of(id, size))].push_back(id);
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i] != 0) nodes_out[static_cast<std::size_t>(home_of(node_ids[i], size))].push_back(node_ids[i]);
  }
  const auto faces_in = exchange(comm, faces_out, c);
  const auto nodes_in = exchange(comm, nodes_out, c);
  std::vector<std::vector<long>> shared_out(p);
  LocalError error;
  capture_error(error, [&] {
    std::unordered_map<long, int> face_rank;
    for (int r = 0; r < size; ++r) {
      for (long id : faces_in[static_cast<std::size_t>(r)]) {
        const auto [at, inserted] = face_rank.emplace(id, r);
        CONTACTNN_REQUIRE_AS(InvalidArgument, inserted,
                             "contact search under MPI: face id " << id << " given twice (by rank "
                                                                  << at->second << " and by rank " << r
                                                                  << ")");
      }
    }
    std::unordered_map<long, int> node_ranks;
    for (const auto& ids : nodes_in)
      for (long id : ids) ++node_ranks[id];
    for (int r = 0; r < size; ++r) {
      for (long id : nodes_in[static_cast<std::size_t>(r)]) {
        if (node_ranks[id] > 1) shared_out[static_cast<std::size_t>(r)].push_back(id);
      }
    }
  });
  agree(comm, error, c);
  const auto shared_in = exchange(comm, shared_out, c);
  for (const auto& ids : shared_in)
    for (long id : ids) interface_nodes.push_back(by_id.at(id));
  std::sort(interface_nodes.begin(), interface_nodes.end());
}

DistributedContactSearch::DistributedContactSearch(MPI_Comm comm, std::span<const long> face_ids,
                                                   std::span<const mesh::FaceType> face_types,
                                                   std::span<const long> connectivity,
                                                   std::span<const long> node_ids,
                                                   std::span<const long> slave_nodes,
                                                   const contact::ContactSearchOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  check_mpi(MPI_Comm_dup(comm, &m.comm), "MPI_Comm_dup");
  MPI_Comm_rank(m.comm, &m.rank);
  MPI_Comm_size(m.comm, &m.size);
  m.options = options;
  m.track = options.tracking;  // of the ghost layer; the local search is fresh (the serial tracker's warm
                               // starts may differ from a fresh search in the last bits)
  m.options.tracking = false;

  // Local checks; every rank agrees on the outcome before anything is exchanged.
  ExchangeCounts c;
  LocalError error;
  capture_error(error, [&] {
    m.check_options();
    m.index_nodes(node_ids);
    m.index_faces(face_ids, face_types, connectivity);
    m.index_slaves(slave_nodes);
  });
  agree(m.comm, error, c);
  m.face_ids.assign(face_ids.begin(), face_ids.end());
  m.face_types.assign(face_types.begin(), face_types.end());
  m.connectivity.assign(connectivity.begin(), connectivity.end());
  m.node_ids.assign(node_ids.begin(), node_ids.end());
  m.slave_ids.assign(slave_nodes.begin(), slave_nodes.end());
  m.find_interface_nodes(c);
  m.counts = c;
}

DistributedContactSearch::~DistributedContactSearch() = default;

int DistributedContactSearch::rank() const { return impl_->rank; }
int DistributedContactSearch::size() const { return impl_->size; }
const ExchangeCounts& DistributedContactSearch::counts() const { return impl_->counts; }

// 1. Local checks: the arrays' sizes and the coordinates of the nodes used.
void DistributedContactSearch::Impl::check_update(const DistributedResults& out) const {
  const std::size_t n = slave_ids.size();
  CONTACTNN_REQUIRE_AS(InvalidArgument, coordinates.size() == 3 * node_ids.size(),
                       "contact search under MPI update: " << coordinates.size()
                                                           << " coordinates, expected 3 x " << node_ids.size()
                                                           << " nodes");
  contact::check_output_sizes("contact search under MPI update", out, n);
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i] == 0) continue;
    const Vec3 x = node_at(static_cast<int>(i));
    if (!x.allFinite()) {
      std::ostringstream os;
      os << "contact search under MPI update: node " << node_ids[i] << " has a non-finite coordinate ("
         << x.x() << ", " << x.y() << ", " << x.z() << ")";
      throw NumericalError(os.str());
    }
  }
}

// 2. The interface nodes' copies compared at their home ranks (sent even after a local error, empty, so that
// every rank takes part in the exchange).
void DistributedContactSearch::Impl::compare_interface_copies(LocalError& error, ExchangeCounts& c) {
  std::vector<std::vector<NodeCopy>> copies_out(static_cast<std::size_t>(size));
  if (error.kind == ErrorKind::kNone) {
    for (int i : interface_nodes) {
      const long id = node_ids[static_cast<std::size_t>(i)];
      const Vec3 x = node_at(i);
      copies_out[static_cast<std::size_t>(home_of(id, size))].push_back({id, {x.x(), x.y(), x.z()}});
    }
  }
  const auto copies_in = exchange(comm, copies_out, c);
  capture_error(error, [&] {
    std::unordered_map<long, std::pair<int, NodeCopy>> first;
    for (int r = 0; r < size; ++r) {
      for (const NodeCopy& copy : copies_in[static_cast<std::size_t>(r)]) {
        const auto [at, inserted] = first.emplace(copy.id, std::pair(r, copy));
        const NodeCopy& a = at->second.second;
        const bool same = a.x[0] == copy.x[0] && a.x[1] == copy.x[1] && a.x[2] == copy.x[2];
        CONTACTNN_REQUIRE_AS(InvalidArgument, inserted || same,
                             "contact search under MPI update: node id "
                                 << copy.id << " is (" << a.x[0] << ", " << a.x[1] << ", " << a.x[2]
                                 << ") on rank " << at->second.first << " and (" << copy.x[0] << ", "
                                 << copy.x[1] << ", " << copy.x[2] << ") on rank " << r
                                 << ": two different nodes under one global id");
      }
    }
  });
}

// 3. This rank's faces' boxes, and (as the one allreduce of step 3 wants them) its largest face size, the
// largest growth of its faces' boxes and the largest movement of its slave nodes since the last exchange of
// faces.
std::array<double, 3> DistributedContactSearch::Impl::sizes_and_movement(
    std::vector<std::array<double, 6>>& boxes) const {
  const std::size_t faces = face_ids.size();
  boxes.resize(faces);
  std::array<double, 3> local{0.0, 0.0, 0.0};
  std::vector<Vec3> x;
  for (std::size_t f = 0; f < faces; ++f) {
    const int k = face_node_count(face_types[f]);
    const int corners =
        face_types[f] == mesh::FaceType::kQuad4 || face_types[f] == mesh::FaceType::kQuad8 ? 4 : 3;
    x.clear();
    for (int j = 0; j < k; ++j)
      x.push_back(node_at(face_nodes[static_cast<std::size_t>(face_offsets[f] + j)]));
    local[0] =
        std::max(local[0], face_size(std::span<const Vec3>(x).first(static_cast<std::size_t>(corners))));
    boxes[f] = face_box(face_types[f], x);
  }
  if (!exchanged) return local;
  for (std::size_t f = 0; f < faces; ++f) {
    // A face's box grows by at most its nodes' movement (corners), or 9 times it (a quadratic face: the
    // corners', and the bulge of 4 edges, each mid-side offset moving at most twice the nodes' movement).
    const int k = face_node_count(face_types[f]);
    const double growth = k == 4 || k == 3 ? 1.0 : 9.0;
    for (int j = 0; j < k; ++j) {
      const int i = face_nodes[static_cast<std::size_t>(face_offsets[f] + j)];
      local[1] = std::max(local[1], growth * (node_at(i) - reference[static_cast<std::size_t>(i)]).norm());
    }
  }
  for (int s : slave_nodes)
    local[2] = std::max(local[2], (node_at(s) - reference[static_cast<std::size_t>(s)]).norm());
  return local;
}

// 4. The ghost layer, chosen afresh: every rank's slave box (MPI_Allgather), then each rank's faces within
// reach of another rank's slave box sent to it (faces without coordinates: those travel at every update),
// and this rank's own faces within reach of its slaves kept.
void DistributedContactSearch::Impl::choose_ghost_faces(const std::vector<std::array<double, 6>>& boxes,
                                                        ExchangeCounts& c) {
  const auto p = static_cast<std::size_t>(size);
  reference.assign(coordinates.size() / 3, Vec3::Zero());
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i] != 0) reference[i] = node_at(static_cast<int>(i));
  }
  exchanged = true;
  const std::array<double, 6> mine = slave_box(slave_nodes, [&](int i) { return node_at(i); });
  std::vector<double> all_boxes(6 * p);
  ++c.collectives;
  check_mpi(MPI_Allgather(mine.data(), 6, MPI_DOUBLE, all_boxes.data(), 6, MPI_DOUBLE, comm),
            "MPI_Allgather");
  c.bytes_sent += static_cast<long>(6 * sizeof(double) * (p - 1));
  c.messages_sent += static_cast<long>(p - 1);

  std::vector<std::vector<long>> faces_out(p);
  std::vector<std::vector<int>> send(p);
  std::vector<LocalFace> kept;
  for (std::size_t f = 0; f < face_ids.size(); ++f) {
    const int k = face_node_count(face_types[f]);
    const auto first = static_cast<std::size_t>(face_offsets[f]);
    for (int r = 0; r < size; ++r) {
      if (!boxes_meet(boxes[f], &all_boxes[6 * static_cast<std::size_t>(r)], reach)) continue;
      if (r == rank) {
        LocalFace face{face_ids[f], rank, face_types[f], {}};
        for (int j = 0; j < k; ++j)
          face.nodes[static_cast<std::size_t>(j)] = connectivity[first + static_cast<std::size_t>(j)];
        kept.push_back(face);
        continue;
      }
      const auto u = static_cast<std::size_t>(r);
      faces_out[u].push_back(face_ids[f]);
      faces_out[u].push_back(static_cast<long>(face_types[f]));
      for (int j = 0; j < k; ++j) {
        faces_out[u].push_back(connectivity[first + static_cast<std::size_t>(j)]);
        send[u].push_back(face_nodes[first + static_cast<std::size_t>(j)]);
      }
      ++c.ghost_faces_sent;
    }
  }
  const auto faces_in = exchange(comm, faces_out, c);
  std::vector<std::vector<long>> recv_ids(p);
  for (int r = 0; r < size; ++r) {
    const auto& words = faces_in[static_cast<std::size_t>(r)];
    std::size_t at = 0;
    while (at < words.size()) {
      LocalFace face{words[at], r, static_cast<mesh::FaceType>(words[at + 1]), {}};
      const int k = face_node_count(face.type);
      at += 2;
      for (int j = 0; j < k; ++j) {
        face.nodes[static_cast<std::size_t>(j)] = words[at + static_cast<std::size_t>(j)];
        recv_ids[static_cast<std::size_t>(r)].push_back(words[at + static_cast<std::size_t>(j)]);
      }
      at += static_cast<std::size_t>(k);
      kept.push_back(face);
      ++c.ghost_faces_received;
    }
  }
  adopt_local_faces(std::move(kept), std::move(send), std::move(recv_ids));
}

// The local search's faces (own within reach and ghosts) in increasing global face id, their nodes and the
// slave nodes in increasing global id (the same order whatever the split), and where each node's
// coordinates come from: each node's coordinates travel once per sender and update, in increasing global id.
void DistributedContactSearch::Impl::adopt_local_faces(std::vector<LocalFace> kept,
                                                       std::vector<std::vector<int>> send,
                                                       std::vector<std::vector<long>> recv_ids) {
  std::sort(kept.begin(), kept.end(), [](const LocalFace& a, const LocalFace& b) { return a.id < b.id; });
  for (std::size_t r = 0; r < send.size(); ++r) {
    sort_unique(send[r], [&](int a, int b) {
      return node_ids[static_cast<std::size_t>(a)] < node_ids[static_cast<std::size_t>(b)];
    });
    sort_unique(recv_ids[r]);
  }
  send_nodes = std::move(send);
  std::vector<long> ids;
  for (const LocalFace& f : kept)
    ids.insert(ids.end(), f.nodes.begin(), f.nodes.begin() + face_node_count(f.type));
  for (long id : slave_ids) ids.push_back(id);
  sort_unique(ids);
  const auto slot_of = [&](long id) {
    return static_cast<int>(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
  };
  own_slots.clear();
  for (std::size_t i = 0; i < node_ids.size(); ++i) {
    if (used[i] == 0) continue;
    const auto at = std::lower_bound(ids.begin(), ids.end(), node_ids[i]);
    if (at != ids.end() && *at == node_ids[i]) own_slots.emplace_back(static_cast<int>(i), slot_of(*at));
  }
  recv_slots.assign(recv_ids.size(), {});
  for (std::size_t r = 0; r < recv_ids.size(); ++r)
    for (long id : recv_ids[r]) recv_slots[r].push_back(slot_of(id));
  local_face_id.clear();
  local_face_owner.clear();
  local_types.clear();
  local_connectivity.clear();
  handle.reset();
  local_ids = std::move(ids);
  for (const LocalFace& f : kept) {
    local_types.push_back(f.type);
    local_connectivity.insert(local_connectivity.end(), f.nodes.begin(),
                              f.nodes.begin() + face_node_count(f.type));
    local_face_id.push_back(f.id);
    local_face_owner.push_back(f.owner);
  }
}

// 5. The coordinates of the ghost faces' nodes, from their owners (every update).
std::vector<std::vector<double>> DistributedContactSearch::Impl::exchange_ghost_coordinates(
    ExchangeCounts& c) const {
  std::vector<std::vector<double>> xyz_out(send_nodes.size());
  for (std::size_t r = 0; r < send_nodes.size(); ++r) {
    for (int i : send_nodes[r]) {
      const Vec3 y = node_at(i);
      xyz_out[r].insert(xyz_out[r].end(), {y.x(), y.y(), y.z()});
    }
  }
  auto xyz_in = exchange(comm, xyz_out, c);
  for (const auto& v : xyz_in) c.ghost_nodes_received += static_cast<long>(v.size() / 3);
  return xyz_in;
}

// 6. The local search over the local faces, fresh. The serial handle's capture distance is fixed at its
// creation: a new handle where this increment's differs (the default capture distance follows the largest
// face size; creating a handle builds its surface only).
void DistributedContactSearch::Impl::search_locally(double capture,
                                                    const std::vector<std::vector<double>>& xyz_in,
                                                    ContactAnswers& a) {
  if (slave_ids.empty() || local_types.empty()) return;
  if (!handle || handle_capture != capture) {
    contact::ContactSearchOptions o = options;
    o.capture_distance = capture;
    handle.reset();
    handle = std::make_unique<contact::ContactSearch>(
        local_types, local_connectivity,
        contact::NodeNumbering{static_cast<long>(local_ids.size()), 0, local_ids},
        contact::SlavePoints{slave_ids, 0}, o);
    handle_capture = capture;
  }
  std::vector<double> coords(3 * local_ids.size(), 0.0);
  for (const auto& [i, slot] : own_slots) {
    for (std::size_t k = 0; k < 3; ++k)
      coords[3 * static_cast<std::size_t>(slot) + k] = coordinates[3 * static_cast<std::size_t>(i) + k];
  }
  for (std::size_t r = 0; r < recv_slots.size(); ++r) {
    for (std::size_t j = 0; j < recv_slots[r].size(); ++j) {
      for (std::size_t k = 0; k < 3; ++k)
        coords[3 * static_cast<std::size_t>(recv_slots[r][j]) + k] = xyz_in[r][3 * j + k];
    }
  }
  handle->update(coords, {}, {a.status, a.face, a.location, a.param, a.point, a.gap, a.normal});
}

// 7. The answers, the face as its global id and owner rank.
void DistributedContactSearch::Impl::write_answers(const ContactAnswers& a,
                                                   const DistributedResults& out) const {
  for (std::size_t i = 0; i < slave_ids.size(); ++i) {
    const bool found = a.face[i] >= 0;
    out.status[i] = a.status[i];
    out.face[i] = found ? local_face_id[static_cast<std::size_t>(a.face[i])] : -1;
    if (!out.owner.empty()) out.owner[i] = found ? local_face_owner[static_cast<std::size_t>(a.face[i])] : -1;
    if (!out.location.empty()) out.location[i] = a.location[i];
    if (!out.gap.empty()) out.gap[i] = a.gap[i];
    for (std::size_t k = 0; k < 2 && !out.param.empty(); ++k) out.param[2 * i + k] = a.param[2 * i + k];
    for (std::size_t k = 0; k < 3; ++k) {
      if (!out.point.empty()) out.point[3 * i + k] = a.point[3 * i + k];
      if (!out.normal.empty()) out.normal[3 * i + k] = a.normal[3 * i + k];
    }
  }
}

void DistributedContactSearch::update(std::span<const double> coordinates, const DistributedResults& out) {
  Impl& m = *impl_;
  m.coordinates = coordinates;
  ExchangeCounts c;

  // 1-2. Local checks, the interface nodes' copies compared at their home ranks, one agreement.
  LocalError error;
  capture_error(error, [&] { m.check_update(out); });
  m.compare_interface_copies(error, c);
  agree(m.comm, error, c);

  // 3. The capture distance (the option's, or the largest face size over all ranks) and the movement since
  // the last exchange of faces, in one MPI_Allreduce (max): the largest face size, the growth of the faces'
  // boxes and the slave nodes' movement.
  std::vector<std::array<double, 6>> boxes;
  const std::array<double, 3> local = m.sizes_and_movement(boxes);
  std::array<double, 3> global{0.0, 0.0, 0.0};
  allreduce(local.data(), global.data(), 3, MPI_DOUBLE, MPI_MAX, m.comm, c, "MPI_Allreduce (sizes)");
  const contact::SearchOptions defaults;
  const double capture =
      m.options.capture_distance > 0.0 ? m.options.capture_distance : defaults.capture_relative * global[0];
  // The reach a face must come within of a rank's slave box: the capture distance, widened against rounding
  // and SPEC 9's tie band (1e-12 of a face size), so that a face the serial search could weigh is never left
  // out.
  const double needed = capture * (1.0 + 1e-9) + 1e-9 * global[0];
  // The faces exchanged last still hold every face the search needs while the capture distance plus the
  // growth of the faces' boxes (global[1]) and the slave nodes' movement (global[2]) since fits in the reach
  // they were chosen with. The same decision on every rank.
  if (!m.track || !m.exchanged || needed + global[1] + global[2] > m.reach) {
    c.exchanged = 1;
    m.reach = needed + kBudget * capture;
    m.choose_ghost_faces(boxes, c);  // 4
  }
  c.faces_searched = static_cast<long>(m.local_face_id.size());

  // 5-6. The ghost faces' coordinates and the local search, whose errors every rank agrees on.
  const auto xyz_in = m.exchange_ghost_coordinates(c);
  ContactAnswers answers(m.slave_ids.size(), static_cast<int>(Status::kNoSegment), -1);
  capture_error(error, [&] { m.search_locally(capture, xyz_in, answers); });
  agree(m.comm, error, c);

  m.write_answers(answers, out);  // 7
  m.counts = c;
  m.coordinates = {};
}

}  // namespace contactnn::mpi
