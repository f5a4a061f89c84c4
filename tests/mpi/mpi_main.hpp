// The main of the MPI test programs (tests/mpi): MPI started and ended around run(argc, argv, rank, size),
// and a contactnn::Error answered by on_error(error, rank), which gives the exit status.
#pragma once

#include <mpi.h>

#include "core/error.hpp"

namespace contactnn::mpi_test {

template <class Run, class OnError>
int mpi_main(int argc, char** argv, const Run& run, const OnError& on_error) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int code = 0;
  try {
    code = run(argc, argv, rank, size);
  } catch (const Error& e) {
    code = on_error(e, rank);
  }
  MPI_Finalize();
  return code;
}

}  // namespace contactnn::mpi_test
