// mpi_communication: what the distributed contact search (lib/mpi, issue 41) sends, on a history split over
// the ranks of mpirun (scripts/mpi-communication runs it on the 1e6-node history and writes results/mpi.md).
//
//   mpi_communication --deck D.inp --results R.frd --output F.csv [--split slab,bisection] [--tracking
//   on,off]
//                     [--pair K] [--check on|off]
//     Every rank reads the deck and the results, splits the pair's master faces and slave nodes over the
//     ranks (slab: P slabs along x with equal face counts; bisection: recursive coordinate bisection of the
//     face centres, each cut across the longest extent, P parts of equal face count), each slave node to the
//     part whose cuts hold it, and runs the distributed search through every increment of the results file.
//     Rank 0 writes F.csv (atomically): per stage (create, then each increment) and rank, the ExchangeCounts
//     and the rank's own faces, slave nodes and nodes. --check on (the default): every rank also runs the
//     serial contact::ContactSearch over all the faces and compares its slave nodes' answers bit for bit.
//   Exit status: 0 written and (with --check) every answer identical; 1 otherwise; 2 usage.
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/scene.hpp"
#include "core/error.hpp"
#include "deck_input.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "mpi/distributed_contact_search.hpp"
#include "mpi_main.hpp"

namespace {

using namespace contactnn;
using geometry::Vec3;

std::string arg(int argc, char** argv, const std::string& name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == name) return argv[i + 1];
  return fallback;
}

/// Recursive coordinate bisection: faces (by centre) and slave nodes in ranks [r0, r1), each cut at the face
/// count's share of the ranks, across `axis` (-1: the longest extent of the face centres).
void bisect(std::vector<std::size_t> faces, std::vector<std::size_t> slaves, int r0, int r1, int axis,
            const std::vector<Vec3>& centre, const std::vector<Vec3>& slave_at, std::vector<int>& face_rank,
            std::vector<int>& slave_rank) {
  if (r1 - r0 == 1) {
    for (std::size_t f : faces) face_rank[f] = r0;
    for (std::size_t s : slaves) slave_rank[s] = r0;
    return;
  }
  Eigen::Index k = axis;
  if (k < 0) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (std::size_t f : faces) {
      lo = lo.cwiseMin(centre[f]);
      hi = hi.cwiseMax(centre[f]);
    }
    (hi - lo).maxCoeff(&k);
  }
  std::stable_sort(faces.begin(), faces.end(),
                   [&](std::size_t a, std::size_t b) { return centre[a][k] < centre[b][k]; });
  const int middle = r0 + (r1 - r0) / 2;
  const std::size_t cut =
      faces.size() * static_cast<std::size_t>(middle - r0) / static_cast<std::size_t>(r1 - r0);
  double plane = std::numeric_limits<double>::infinity();
  if (cut == 0) plane = -plane;
  if (cut > 0 && cut < faces.size()) plane = 0.5 * (centre[faces[cut - 1]][k] + centre[faces[cut]][k]);
  std::vector<std::size_t> left_slaves, right_slaves;
  for (std::size_t s : slaves) (slave_at[s][k] < plane ? left_slaves : right_slaves).push_back(s);
  std::vector<std::size_t> right(faces.begin() + static_cast<long>(cut), faces.end());
  faces.resize(cut);
  bisect(std::move(faces), std::move(left_slaves), r0, middle, axis, centre, slave_at, face_rank, slave_rank);
  bisect(std::move(right), std::move(right_slaves), middle, r1, axis, centre, slave_at, face_rank,
         slave_rank);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

/// The columns of one row per rank and stage.
constexpr const char* kColumns =
    "bytes_sent,header_bytes_sent,messages_sent,collectives,allreduces,ghost_faces_sent,ghost_faces_received,"
    "ghost_nodes_received,faces_searched,exchanged,own_faces,own_slaves,own_nodes";
constexpr int kCount = 13;

std::vector<long> row_of(const mpi::ExchangeCounts& c, std::size_t faces, std::size_t slaves,
                         std::size_t nodes) {
  return {c.bytes_sent,
          c.header_bytes_sent,
          c.messages_sent,
          c.collectives,
          c.allreduces,
          c.ghost_faces_sent,
          c.ghost_faces_received,
          c.ghost_nodes_received,
          c.faces_searched,
          c.exchanged,
          static_cast<long>(faces),
          static_cast<long>(slaves),
          static_cast<long>(nodes)};
}

/// One rank's share of a split, and the distributed search over it.
struct Share {
  std::string split;
  bool tracking = true;
  std::vector<long> face_ids, connectivity, node_ids, slaves;
  std::vector<mesh::FaceType> types;
  std::vector<std::size_t> my_slaves;  ///< index in the deck's slave nodes of each of `slaves`
  std::unique_ptr<mpi::DistributedContactSearch> search;
  long mismatches = 0, found = 0;
};

Share share_of(const mpi_test::Input& in, const contact::Scene& scene, const std::string& split, int rank,
               int size) {
  const std::size_t faces = in.types.size(), m = scene.slave_ids.size();
  std::vector<int> face_rank(faces), slave_rank(m);
  const std::vector<double> x = mpi_test::coordinates(in, scene);
  const auto at = [&](long id) {
    const std::size_t i = in.index(id);
    return Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  };
  std::vector<Vec3> centre(faces, Vec3::Zero()), slave_at(m);
  std::vector<std::size_t> all_faces(faces), all_slaves(m);
  for (std::size_t f = 0; f < faces; ++f) {
    all_faces[f] = f;
    const auto b = static_cast<std::size_t>(in.offsets[f]), e = static_cast<std::size_t>(in.offsets[f + 1]);
    for (std::size_t j = b; j < e; ++j) centre[f] += at(in.connectivity[j]);
    centre[f] /= static_cast<double>(e - b);
  }
  for (std::size_t i = 0; i < m; ++i) {
    all_slaves[i] = i;
    slave_at[i] = at(scene.slave_ids[i]);
  }
  bisect(all_faces, all_slaves, 0, size, split == "slab" ? 0 : -1, centre, slave_at, face_rank, slave_rank);

  Share s;
  s.split = split;
  std::vector<char> mine(in.ids.size(), 0);
  for (std::size_t f = 0; f < faces; ++f) {
    if (face_rank[f] != rank) continue;
    s.face_ids.push_back(static_cast<long>(f));
    s.types.push_back(in.types[f]);
    for (auto j = static_cast<std::size_t>(in.offsets[f]); j < static_cast<std::size_t>(in.offsets[f + 1]);
         ++j) {
      s.connectivity.push_back(in.connectivity[j]);
      mine[in.index(in.connectivity[j])] = 1;
    }
  }
  for (std::size_t i = 0; i < m; ++i) {
    if (slave_rank[i] != rank) continue;
    s.my_slaves.push_back(i);
    s.slaves.push_back(scene.slave_ids[i]);
    mine[in.index(scene.slave_ids[i])] = 1;
  }
  for (std::size_t i = 0; i < in.ids.size(); ++i)
    if (mine[i] != 0) s.node_ids.push_back(in.ids[i]);
  return s;
}

/// The serial search's answers for every slave node.
using Answers = contact::ContactAnswers;

/// One increment of one share: the distributed search, checked against the serial answers `s` (when given).
void update_share(Share& share, const mpi_test::Input& in, const std::vector<double>& all, const Answers* s) {
  std::vector<double> x;
  x.reserve(3 * share.node_ids.size());
  for (long id : share.node_ids) {
    const std::size_t i = in.index(id);
    x.insert(x.end(), {all[3 * i], all[3 * i + 1], all[3 * i + 2]});
  }
  const std::size_t k = share.slaves.size();
  std::vector<int> status(k), owner(k), location(k);
  std::vector<long> face(k);
  std::vector<double> param(2 * k), point(3 * k), gap(k), normal(3 * k);
  share.search->update(x, {status, face, owner, location, param, point, gap, normal});
  if (s == nullptr) return;
  for (std::size_t j = 0; j < k; ++j) {
    const std::size_t i = share.my_slaves[j];
    bool same = status[j] == s->status[i] && face[j] == s->face[i] && location[j] == s->location[i] &&
                same_bits(gap[j], s->gap[i]);
    for (std::size_t c = 0; c < 2; ++c) same = same && same_bits(param[2 * j + c], s->param[2 * i + c]);
    for (std::size_t c = 0; c < 3; ++c)
      same = same && same_bits(point[3 * j + c], s->point[3 * i + c]) &&
             same_bits(normal[3 * j + c], s->normal[3 * i + c]);
    share.mismatches += same ? 0 : 1;
    share.found += s->face[i] >= 0 ? 1 : 0;
  }
}

std::vector<std::string> words(const std::string& list) {
  std::vector<std::string> out;
  std::size_t at = 0;
  while (at <= list.size()) {
    const std::size_t comma = std::min(list.find(',', at), list.size());
    out.push_back(list.substr(at, comma - at));
    at = comma + 1;
  }
  return out;
}

int run(int argc, char** argv, int rank, int size) {
  const std::string deck = arg(argc, argv, "--deck", ""), frd = arg(argc, argv, "--results", "");
  const std::string output = arg(argc, argv, "--output", "");
  const bool check = arg(argc, argv, "--check", "on") == "on";
  const int pair = std::stoi(arg(argc, argv, "--pair", "0"));
  const std::vector<std::string> splits = words(arg(argc, argv, "--split", "slab,bisection"));
  const std::vector<std::string> trackings = words(arg(argc, argv, "--tracking", "on,off"));
  bool usage = deck.empty() || frd.empty() || output.empty();
  for (const auto& w : splits) usage = usage || (w != "slab" && w != "bisection");
  for (const auto& w : trackings) usage = usage || (w != "on" && w != "off");
  if (usage) {
    if (rank == 0)
      std::fprintf(stderr, "mpi_communication: see the usage at the top of mpi_communication.cpp\n");
    return 2;
  }
  mesh::ContactModel model = io::read_inp_deck(deck);
  const io::FrdResults results = io::read_frd(frd);
  contact::Scene scene = contact::make_scene(model, pair);
  const mpi_test::Input in = mpi_test::input_of(scene);
  const std::size_t m = scene.slave_ids.size();

  std::vector<Share> shares;
  for (const auto& split : splits) {
    for (const auto& tracking : trackings) {
      Share s = share_of(in, scene, split, rank, size);
      s.tracking = tracking == "on";
      contact::ContactSearchOptions options;
      options.tracking = s.tracking;
      s.search = std::make_unique<mpi::DistributedContactSearch>(
          MPI_COMM_WORLD, s.face_ids, s.types, s.connectivity, s.node_ids, s.slaves, options);
      shares.push_back(std::move(s));
    }
  }
  std::unique_ptr<contact::ContactSearch> serial;
  contact::ContactSearchOptions serial_options;
  serial_options.tracking = false;
  if (check)
    serial = std::make_unique<contact::ContactSearch>(
        in.types, in.connectivity, contact::NodeNumbering{static_cast<long>(in.ids.size()), 0, in.ids},
        contact::SlavePoints{scene.slave_ids, 0}, serial_options);

  std::vector<std::string> rows;  // rank 0: the CSV's rows
  const auto gather = [&](const Share& s, const std::string& stage) {
    const std::vector<long> row =
        row_of(s.search->counts(), s.face_ids.size(), s.slaves.size(), s.node_ids.size());
    std::vector<long> all(static_cast<std::size_t>(kCount * size));
    MPI_Gather(row.data(), kCount, MPI_LONG, all.data(), kCount, MPI_LONG, 0, MPI_COMM_WORLD);
    for (int r = 0; r < size && rank == 0; ++r) {
      std::string line =
          s.split + "," + (s.tracking ? "tracked" : "fresh") + "," + stage + "," + std::to_string(r);
      for (int c = 0; c < kCount; ++c)
        line += "," + std::to_string(all[static_cast<std::size_t>(r * kCount + c)]);
      rows.push_back(line);
    }
  };
  for (const Share& s : shares) gather(s, "create");
  Answers answers(m);
  for (std::size_t increment = 0; increment < results.increments.size(); ++increment) {
    io::move_to_increment(model.mesh, results, increment);
    scene = contact::make_scene(model, pair);
    const std::vector<double> all = mpi_test::coordinates(in, scene);
    if (serial) serial->update(all, {}, answers.results());
    for (Share& s : shares) {
      update_share(s, in, all, serial ? &answers : nullptr);
      gather(s, std::to_string(increment + 1));
    }
  }
  long mismatches = 0, found = 0;
  for (const Share& s : shares) {
    long totals[2] = {s.mismatches, s.found}, global[2] = {0, 0};
    MPI_Allreduce(totals, global, 2, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    mismatches += global[0];
    found += global[1];
    if (rank == 0 && check)
      std::printf("%s split %s on %d ranks, %s: %ld answers found, %ld differ from the serial search\n",
                  deck.c_str(), s.split.c_str(), size, s.tracking ? "tracked" : "fresh", global[1],
                  global[0]);
  }
  const bool ok = !check || (mismatches == 0 && found > 0);
  if (rank != 0) return ok ? 0 : 1;
  const std::string tmp = output + ".tmp";
  {
    std::ofstream csv(tmp);
    csv << "split,ghosts,increment,rank," << kColumns << "\n";
    for (const auto& line : rows) csv << line << "\n";
    if (!csv) throw IoError("mpi_communication: cannot write " + tmp);
  }
  std::rename(tmp.c_str(), output.c_str());
  return ok ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  return contactnn::mpi_test::mpi_main(argc, argv, run, [](const contactnn::Error& e, int rank) {
    std::fprintf(stderr, "mpi_communication rank %d: %s\n", rank, e.what());
    return 1;
  });
}
