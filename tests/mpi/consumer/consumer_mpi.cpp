// A consumer of the installed mpi component, under mpirun -np 2: the plate of consumer_contact.cpp, face r on
// rank r and the slave node above the other rank's face, searched through the C++ class
// (contactnn::mpi::DistributedContactSearch) and the C handle (contactnn_mpi.h). Prints PASS on rank 0 when,
// on both ranks and through both, the slave node finds the other rank's face, its owner and gap 0.25.
#include <contactnn/contactnn_mpi.h>
#include <mpi.h>

#include <cmath>
#include <contactnn/mpi/distributed_contact_search.hpp>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  using namespace contactnn;
  const int other = 1 - rank;
  // Plate nodes 1..6 as in consumer_contact.cpp; face r holds nodes (1 + r, 2 + r, 5 + r, 4 + r); slave node
  // 7 + r lies 0.25 above face r's centre.
  const std::vector<long> face_ids{rank};
  const std::vector<mesh::FaceType> types{mesh::FaceType::kQuad4};
  const std::vector<long> connectivity{1 + rank, 2 + rank, 5 + rank, 4 + rank};
  const std::vector<long> slaves{7 + other};
  const std::vector<long> nodes{1 + rank, 2 + rank, 5 + rank, 4 + rank, 7 + other};
  std::vector<double> x;
  for (long id : nodes) {
    if (id <= 6)
      x.insert(x.end(), {static_cast<double>((id - 1) % 3), static_cast<double>((id - 1) / 3), 0.0});
    else
      x.insert(x.end(), {0.5 + static_cast<double>(id - 7), 0.5, 0.25});
  }
  bool ok = size == 2;
  {
    mpi::DistributedContactSearch search(MPI_COMM_WORLD, face_ids, types, connectivity, nodes, slaves);
    std::vector<int> status(1), owner(1);
    std::vector<long> face(1);
    std::vector<double> gap(1);
    search.update(x, {status, face, owner, {}, {}, {}, gap, {}});
    ok = ok && status[0] == 0 && face[0] == other && owner[0] == other && std::abs(gap[0] - 0.25) < 1e-12;
  }
  contactnn_mpi_contact* c = nullptr;
  const int type = CONTACTNN_FACE_QUAD4;
  int code = contactnn_mpi_contact_create(&c, MPI_COMM_WORLD, 1, face_ids.data(), &type, connectivity.data(),
                                          5, nodes.data(), 1, slaves.data(), nullptr);
  int status = -1, owner = -1;
  long face = -1;
  double gap = 0.0;
  if (code == CONTACTNN_SUCCESS)
    code = contactnn_mpi_contact_update(c, 5, x.data(), 1, &status, &face, &owner, nullptr, nullptr, nullptr,
                                        &gap, nullptr);
  ok = ok && code == CONTACTNN_SUCCESS && status == 0 && face == other && owner == other &&
       std::abs(gap - 0.25) < 1e-12;
  contactnn_mpi_contact_destroy(c);
  int mine = ok ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (rank == 0) std::printf(all != 0 ? "PASS: the mpi component from the installed package\n" : "FAIL\n");
  MPI_Finalize();
  return all != 0 ? 0 : 1;
}
