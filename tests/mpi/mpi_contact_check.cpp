// mpi_contact_check: the distributed contact search (lib/mpi, issue 41) against the serial handle, run under
// mpirun by ctest (tests/mpi/CMakeLists.txt).
//
//   mpi_contact_check --deck D.inp --pair K --split slab|random|empty [--increments N] [--seed S]
//     Every rank reads the deck, splits its master faces and slave nodes over the ranks (slab: by the x of
//     their centre, in P slabs of equal count; random: each to a rank drawn from a seeded generator; empty:
//     random, but rank 0 gets no faces and the last rank no slave nodes), passes its own share to the
//     distributed search, and moves the deck through N increments (the serial test's made-up history). Each
//     rank checks the answers of its slave nodes against a serial contact::ContactSearch over all the faces
//     (given in increasing global face id, the global id being that index): the same status, face, owner
//     rank, location and the same bits of the local coordinates, point, gap and normal. Exit 0 when every
//     answer of every rank is identical and some slave node found a face; prints the bytes each rank sent.
//     --slide F: the slave nodes also slide F face sizes along x per increment.
//   mpi_contact_check --deck D.inp --pair K --hostile duplicate-node|missing-node|nonfinite|duplicate-face
//     Bad input on one rank (run with 3 ranks): exit 0 when every rank ends with the same exception (type and
//     message), 1 otherwise (a deadlock is ctest's timeout).
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/scene.hpp"
#include "contact/surface_search.hpp"
#include "core/error.hpp"
#include "deck_input.hpp"
#include "io/inp_deck.hpp"
#include "mpi/distributed_contact_search.hpp"
#include "mpi_main.hpp"

namespace {

using namespace contactnn;
using contact::Scene;
using geometry::Vec3;

using mpi_test::coordinates;
using mpi_test::Input;
using mpi_test::input_of;

/// test_contact_search.cpp's made-up history: the slave side moves toward and along the master, the master
/// waves.
void move(Scene& scene, int increment, double size, double slide) {
  const double t = 0.05 * size * increment;
  for (Vec3& x : scene.slave_positions) x += Vec3(slide * size, 0.0, 0.0);
  for (Vec3& x : scene.master.positions)
    x += Vec3(0.0, 0.0, 0.02 * size * std::sin(0.7 * increment + x.x() / size) * std::cos(x.y() / size));
  for (Vec3& x : scene.slave_positions) x += Vec3(0.6 * t, 0.3 * t, -0.2 * t);
}

std::string arg(int argc, char** argv, const std::string& name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == name) return argv[i + 1];
  return fallback;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

int run(int argc, char** argv, int rank, int size) {
  const std::string deck = arg(argc, argv, "--deck", "");
  const int pair = std::stoi(arg(argc, argv, "--pair", "0"));
  const std::string split = arg(argc, argv, "--split", "slab");
  const std::string hostile = arg(argc, argv, "--hostile", "");
  const int increments = std::stoi(arg(argc, argv, "--increments", "4"));
  // --slide F: the slave nodes also slide F face sizes along x per increment (beyond the ghost layer's
  // movement budget, so that the faces are chosen again).
  const double slide = std::stod(arg(argc, argv, "--slide", "0"));
  const unsigned seed = static_cast<unsigned>(std::stoul(arg(argc, argv, "--seed", "7")));

  const mesh::ContactModel model = io::read_inp_deck(deck);
  Scene scene = contact::make_scene(model, pair);
  const Input in = input_of(scene);
  const double size_of_face = contact::capture_distance(scene.master, contact::SearchOptions{});
  const auto faces = static_cast<long>(in.types.size());
  const auto m = scene.slave_ids.size();
  const auto node_index = [&](long id) {
    return static_cast<std::size_t>(std::lower_bound(in.ids.begin(), in.ids.end(), id) - in.ids.begin());
  };

  // The split: a rank for every face and every slave node.
  std::vector<int> face_rank(static_cast<std::size_t>(faces)), slave_rank(m);
  {
    const std::vector<double> x = coordinates(in, scene);
    const auto centre_x = [&](long f) {
      double sum = 0.0;
      for (long j = in.offsets[static_cast<std::size_t>(f)]; j < in.offsets[static_cast<std::size_t>(f) + 1];
           ++j)
        sum += x[3 * node_index(in.connectivity[static_cast<std::size_t>(j)])];
      return sum / static_cast<double>(in.offsets[static_cast<std::size_t>(f) + 1] -
                                       in.offsets[static_cast<std::size_t>(f)]);
    };
    if (split == "slab") {
      const auto slabs = [&](std::vector<double> keys, std::vector<int>& out) {
        std::vector<std::size_t> order(keys.size());
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(),
                         [&](std::size_t a, std::size_t b) { return keys[a] < keys[b]; });
        for (std::size_t k = 0; k < order.size(); ++k)
          out[order[k]] = static_cast<int>(k * static_cast<std::size_t>(size) / order.size());
      };
      std::vector<double> fk, sk;
      for (long f = 0; f < faces; ++f) fk.push_back(centre_x(f));
      for (std::size_t i = 0; i < m; ++i) sk.push_back(x[3 * node_index(scene.slave_ids[i])]);
      slabs(fk, face_rank);
      slabs(sk, slave_rank);
    } else {
      std::mt19937 random(seed);
      for (auto& r : face_rank) r = static_cast<int>(random() % static_cast<unsigned>(size));
      for (auto& r : slave_rank) r = static_cast<int>(random() % static_cast<unsigned>(size));
      if (split == "empty" && size > 1) {
        for (auto& r : face_rank) r = r == 0 ? 1 : r;
        for (auto& r : slave_rank) r = r == size - 1 ? size - 2 : r;
      }
    }
  }

  // This rank's share: its faces, the nodes of its faces and slave nodes (in a shuffled order), its slaves.
  std::vector<long> face_ids, connectivity, node_ids, slaves;
  std::vector<mesh::FaceType> types;
  std::vector<char> mine(in.ids.size(), 0);
  for (long f = 0; f < faces; ++f) {
    if (face_rank[static_cast<std::size_t>(f)] != rank) continue;
    face_ids.push_back(f);
    types.push_back(in.types[static_cast<std::size_t>(f)]);
    for (long j = in.offsets[static_cast<std::size_t>(f)]; j < in.offsets[static_cast<std::size_t>(f) + 1];
         ++j) {
      connectivity.push_back(in.connectivity[static_cast<std::size_t>(j)]);
      mine[node_index(in.connectivity[static_cast<std::size_t>(j)])] = 1;
    }
  }
  std::vector<std::size_t> my_slaves;
  for (std::size_t i = 0; i < m; ++i) {
    if (slave_rank[i] != rank) continue;
    my_slaves.push_back(i);
    slaves.push_back(scene.slave_ids[i]);
    mine[node_index(scene.slave_ids[i])] = 1;
  }
  for (std::size_t i = 0; i < in.ids.size(); ++i)
    if (mine[i] != 0) node_ids.push_back(in.ids[i]);
  std::shuffle(node_ids.begin(), node_ids.end(), std::mt19937(seed + static_cast<unsigned>(rank)));

  // The hostile cases: one rank's input made bad.
  std::size_t poisoned = 0;  // index in node_ids of the node made bad at update (nonfinite, duplicate-node)
  if (hostile == "missing-node" && rank == size - 1 && !connectivity.empty()) {
    node_ids.erase(std::find(node_ids.begin(), node_ids.end(), connectivity.front()));
  } else if (hostile == "duplicate-face" && rank == size - 1 && size > 1) {
    // Rank 0's first face again, under its id, with this rank's own first face's nodes.
    const long f = std::find(face_rank.begin(), face_rank.end(), 0) - face_rank.begin();
    if (!face_ids.empty()) face_ids.front() = f;
  } else if (hostile == "duplicate-node" && rank == 1) {
    // A node of rank 0's first face passed here too (as a slave node), moved: two nodes under one id.
    const long f = std::find(face_rank.begin(), face_rank.end(), 0) - face_rank.begin();
    const long id = in.connectivity[static_cast<std::size_t>(in.offsets[static_cast<std::size_t>(f)])];
    if (std::find(node_ids.begin(), node_ids.end(), id) == node_ids.end()) node_ids.push_back(id);
    slaves.push_back(id);
    my_slaves.push_back(m);  // no serial answer to compare: the update must fail
    poisoned = static_cast<std::size_t>(std::find(node_ids.begin(), node_ids.end(), id) - node_ids.begin());
  } else if (hostile == "nonfinite" && rank == 1 && !node_ids.empty()) {
    poisoned = 0;
  }

  contact::ContactSearchOptions options;
  options.tracking = arg(argc, argv, "--tracking", "on") == "on";  // off: the faces exchanged at every update
  mpi::DistributedContactSearch search(MPI_COMM_WORLD, face_ids, types, connectivity, node_ids, slaves,
                                       options);
  contact::ContactSearchOptions serial_options;
  serial_options.tracking = arg(argc, argv, "--serial", "fresh") == "tracked";
  contact::ContactSearch serial(in.types, in.connectivity, {static_cast<long>(in.ids.size()), 0, in.ids},
                                {scene.slave_ids, 0}, serial_options);
  long mismatches = 0, found = 0, exchanges = 0;
  for (int increment = 0; increment < increments; ++increment) {
    if (increment > 0) move(scene, increment, size_of_face, slide);
    const std::vector<double> all = coordinates(in, scene);
    std::vector<double> x;
    for (long id : node_ids) {
      const std::size_t i = node_index(id);
      x.insert(x.end(), {all[3 * i], all[3 * i + 1], all[3 * i + 2]});
    }
    if (hostile == "duplicate-node" && rank == 1) x[3 * poisoned] += 1e-3 * size_of_face;
    if (hostile == "nonfinite" && rank == 1 && !x.empty())
      x[3 * poisoned + 1] = std::numeric_limits<double>::quiet_NaN();

    const std::size_t k = slaves.size();
    std::vector<int> status(k), owner(k), location(k);
    std::vector<long> face(k);
    std::vector<double> param(2 * k), point(3 * k), gap(k), normal(3 * k);
    search.update(x, {status, face, owner, location, param, point, gap, normal});
    contact::ContactAnswers s(m, -7, -7);
    serial.update(all, {}, s.results());
    for (std::size_t j = 0; j < k; ++j) {
      const std::size_t i = my_slaves[j];
      bool same = status[j] == s.status[i] && face[j] == s.face[i] && location[j] == s.location[i] &&
                  owner[j] == (s.face[i] < 0 ? -1 : face_rank[static_cast<std::size_t>(s.face[i])]) &&
                  same_bits(gap[j], s.gap[i]);
      for (std::size_t c = 0; c < 2; ++c) same = same && same_bits(param[2 * j + c], s.param[2 * i + c]);
      for (std::size_t c = 0; c < 3; ++c) {
        same = same && same_bits(point[3 * j + c], s.point[3 * i + c]) &&
               same_bits(normal[3 * j + c], s.normal[3 * i + c]);
      }
      found += s.face[i] >= 0;
      if (!same) {
        if (++mismatches <= 5) {
          std::printf(
              "rank %d increment %d slave %ld: distributed face %ld location %d gap %.17g, serial face %d "
              "location %d gap %.17g\n",
              rank, increment, scene.slave_ids[i], face[j], location[j], gap[j], s.face[i], s.location[i],
              s.gap[i]);
        }
      }
    }
    const mpi::ExchangeCounts& c = search.counts();
    exchanges += c.exchanged;
    std::vector<long> sent(static_cast<std::size_t>(size));
    MPI_Gather(&c.bytes_sent, 1, MPI_LONG, sent.data(), 1, MPI_LONG, 0, MPI_COMM_WORLD);
    if (rank == 0) {
      std::printf("increment %d (%s): bytes sent per rank", increment,
                  c.exchanged != 0 ? "faces exchanged" : "faces kept");
      for (long b : sent) std::printf(" %ld", b);
      std::printf("\n");
    }
  }
  long totals[2] = {mismatches, found}, global[2] = {0, 0};
  MPI_Allreduce(totals, global, 2, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  if (rank == 0) {
    std::printf(
        "%s pair %d split %s on %d ranks, %d increments, %ld exchanges of faces: %ld answers found, %ld "
        "differ "
        "from the serial search\n",
        deck.c_str(), pair, split.c_str(), size, increments, exchanges, global[1], global[0]);
  }
  if (!hostile.empty()) {
    if (rank == 0) std::printf("hostile case %s: no error\n", hostile.c_str());
    return 1;
  }
  return global[0] == 0 && global[1] > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  const bool hostile = !arg(argc, argv, "--hostile", "").empty();
  return contactnn::mpi_test::mpi_main(argc, argv, run, [&](const contactnn::Error& e, int rank) {
    // Every rank must end with the same error: its exit code and a hash of its message agree everywhere.
    const long mine[2] = {e.exit_code(), static_cast<long>(std::hash<std::string>{}(e.what()) >> 1)};
    long low[2] = {0, 0}, high[2] = {0, 0};
    MPI_Allreduce(mine, low, 2, MPI_LONG, MPI_MIN, MPI_COMM_WORLD);
    MPI_Allreduce(mine, high, 2, MPI_LONG, MPI_MAX, MPI_COMM_WORLD);
    const bool same = low[0] == high[0] && low[1] == high[1];
    if (rank == 0) {
      std::printf("every rank: %s error (exit code %d): %s\n", same ? "the same" : "NOT the same",
                  e.exit_code(), e.what());
    }
    return hostile && same ? 0 : 1;
  });
}
