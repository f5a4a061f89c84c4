// search_cxx: contactnn's C++ library (contactnn::runtime: the local search and the network file reader) as a
// C++ finite-element code calls it, on a file of queries, with the headers as the installed package names
// them.
//
// Usage: search_cxx bilinear|gregory METHOD NETWORK RAW.txt OUT.txt
//   RAW.txt  the query count n on the first line, then n rows of 15 (bilinear) or 27 (Gregory) numbers
//   OUT.txt  one line per query: p0 p1 status gap iterations
// Exit status 0, or 1 with the exception's message.
#include <contactnn/core/error.hpp>
#include <contactnn/io/network_model_file.hpp>
#include <contactnn/search/local_search.hpp>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

using namespace contactnn;

int main(int argc, char** argv) {
  if (argc != 6) {
    std::fprintf(stderr, "usage: search_cxx bilinear|gregory METHOD NETWORK RAW.txt OUT.txt\n");
    return 2;
  }
  try {
    // 1. The queries.
    const SurfaceKind kind = surface_from_string(argv[1]);
    const auto columns = static_cast<std::size_t>(search::LocalSearch::raw_columns(kind));
    std::ifstream in(argv[4]);
    std::size_t n = 0;
    in >> n;
    std::vector<double> raw(n * columns);
    for (double& x : raw) {
      std::string token;
      in >> token;
      x = std::stod(token);  // also "nan" and "inf", which operator>> refuses
    }
    CONTACTNN_REQUIRE_AS(FormatError, static_cast<bool>(in),
                         "cannot read " << n << " queries from " << argv[4]);

    // 2. The network and the search.
    const std::unique_ptr<search::NetworkModel> network = io::read_network_model(argv[3]);
    const search::LocalSearch search(kind, search::Method::parse(argv[2]), {}, network.get());

    // 3. One batched call.
    std::vector<double> param(2 * n), gap(n);
    std::vector<Status> status(n);
    std::vector<std::int32_t> iterations(n);
    search.run(n, raw.data(),
               search::Results<double>{param.data(), gap.data(), status.data(), iterations.data()}, 2);

    // 4. The results.
    std::FILE* out = std::fopen(argv[5], "w");
    CONTACTNN_REQUIRE_AS(IoError, out != nullptr, "cannot write " << argv[5]);
    for (std::size_t i = 0; i < n; ++i) {
      std::fprintf(out, "%.17g %.17g %d %.17g %d\n", param[2 * i], param[2 * i + 1],
                   static_cast<int>(status[i]), gap[i], iterations[i]);
    }
    std::fclose(out);
    std::printf("search_cxx: %zu queries\n", n);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "search_cxx: %s\n", e.what());
    return 1;
  }
}
