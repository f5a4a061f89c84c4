// Description: writes the exported C header of a network file (search::export_c_header), for bench_search's
// c-header rows (bench/CMakeLists.txt runs it at build time on the shipped networks). Not an app: train-net
// --export-header is the user's way; this exists so that the benchmark times exactly what an FE code
// compiles.
//
// Sample run:
//   build/bench/export_header data/weights/bilinear-8.h5 /tmp/bilinear_8.h bilinear_8
#include <cstdio>
#include <fstream>

#include "core/error.hpp"
#include "io/network_file.hpp"
#include "search/export_c_header.hpp"

int main(int argc, char** argv) {
  using namespace contactnn;
  if (argc != 4) {
    std::fprintf(stderr, "usage: export_header NETWORK.h5 OUT.h PREFIX\n");
    return 2;
  }
  try {
    const io::TrainedNetwork<float> trained = io::read_network<float>(argv[1]);
    search::CHeaderOptions options;
    options.prefix = argv[3];
    options.description = std::string("network ") + argv[1] + " (bench/export_header)";
    std::ofstream out(argv[2]);
    out << search::export_c_header(search::NetworkModel(trained.network, trained.domain), options);
    CONTACTNN_REQUIRE_AS(IoError, out.good(), "cannot write '" << argv[2] << "'");
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return e.exit_code();
  }
  return 0;
}
