// lib/search/export_c_header: the exported C99 headers compiled by the system C compiler (every header of
// the test in one translation unit, -std=c99 -Wall -Wextra -pedantic -Werror) and run on random queries in
// any node order, on ties, out of the domain, degenerate and non-finite queries; compared with LocalSearch's
// "network" method on the same queries, and the batched entry point with the one-query function.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/network_file.hpp"
#include "search/embedded_sources.hpp"
#include "search/export_c_header.hpp"
#include "search/local_search.hpp"
#include "search/random_queries.hpp"
#include "search/shipped_networks.hpp"

namespace contactnn::search {
namespace {

// The header and the library run the same kernels; they differ only where the C++ build contracts
// multiply-adds (FMA) and the ISO C build does not: ~1e-7 relative per float operation, amplified by the
// output scaling (x 2.5 at most), so below 1e-6; a wrong weight, scaling, symmetry or tie moves results by
// > 1e-3.
constexpr double kFloatNetworkTol = 1e-6;
// Double networks: the same at double rounding.
constexpr double kDoubleNetworkTol = 1e-11;
// Batch against one query where the compiler contracts multiply-adds (GNU C): GCC vectorises other loops of
// the one-query code (across a group of units) and contracts them differently, so the two differ by the
// network's rounding (float: ~1e-7 relative, measured up to 3e-7 absolute), as the header against the
// library. out of a query of status 1 must be left untouched: the driver fills it with this first.
constexpr double kUntouched = 12345.0;

using testing::random_network;
using testing::shipped;

/// One exported header under test and its queries.
struct Case {
  std::string prefix;
  std::shared_ptr<const NetworkModel> model;
  double tol = kFloatNetworkTol;
  std::vector<double> raw;  ///< SPEC 6 rows
};

/// Random queries of the paper's domain (bilinear: then touching contact and random ones again), the ties in
/// every node order, then one each: a slave far above the
/// segment (out of the domain), A = B (degenerate), a NaN coordinate (invalid). Not a multiple of the block
/// width, so the batch's last block is partial.
std::vector<double> queries(SurfaceKind kind, std::uint64_t seed) {
  std::vector<double> raw = testing::random_queries(kind, 203, seed);
  std::mt19937_64 rng(seed + 100);
  if (kind == SurfaceKind::kBilinear) {
    // Touching contact (flat segments, the slave on them), which the float frame leaves to the double pass:
    // after such blocks the batch runs the double pass first (cnn_cff_block_expecting), then random queries
    // again, whose blocks turn it back.
    for (int i = 0; i < 48; ++i) {
      geometry::Configuration c = testing::random_domain_configuration(kind, rng);
      c.nodes[2].z() = 0.0;
      c.slave.z() = 0.0;
      testing::append_raw(testing::place(c, rng, testing::random_order(rng)), kind, raw);
    }
    const std::vector<double> more = testing::random_queries(kind, 40, seed + 7);
    raw.insert(raw.end(), more.begin(), more.end());
    // Kites (|AB| = |AD| at the caller's A) whose slave is nearest B: the one-query function guesses they
    // need the double pass (cnn_cff_looks_undecided), but the float pass decides them, and its answer stands.
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 24; ++i) {
      using geometry::Vec3;
      const geometry::Configuration kite{
          {Vec3(0.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(1.3, 1.3, 0.1 * u(rng)), Vec3(0.0, 1.0, 0.0)},
          Vec3(0.9 + 0.05 * u(rng), 0.15 + 0.05 * u(rng), 0.1 + 0.05 * u(rng)),
          {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}};
      testing::append_raw(testing::place(kite, rng, SquareSymmetry{}), kind, raw);
    }
  }
  for (const geometry::Configuration& c : testing::tie_queries(rng)) testing::append_raw(c, kind, raw);
  const int stride = LocalSearch::raw_columns(kind);
  std::vector<double> far(raw.begin(), raw.begin() + stride), collapsed = far, nan = far;
  {
    // 1e3 element sizes above the segment: along AB x AD / |AB|.
    const double ab[3] = {far[3] - far[0], far[4] - far[1], far[5] - far[2]};
    const double ad[3] = {far[9] - far[0], far[10] - far[1], far[11] - far[2]};
    const double n[3] = {ab[1] * ad[2] - ab[2] * ad[1], ab[2] * ad[0] - ab[0] * ad[2],
                         ab[0] * ad[1] - ab[1] * ad[0]};
    const double length_ab = std::sqrt(ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2]);
    for (int k = 0; k < 3; ++k) far[12 + static_cast<std::size_t>(k)] += 1e3 * n[k] / length_ab;
  }
  for (int k = 0; k < 3; ++k) collapsed[3 + k] = collapsed[k];
  nan[7] = std::numeric_limits<double>::quiet_NaN();
  for (const auto* row : {&far, &collapsed, &nan}) raw.insert(raw.end(), row->begin(), row->end());
  return raw;
}

/// One folder per test: ctest runs the tests of this file in parallel.
std::filesystem::path work_dir(const std::string& test) {
  const auto dir = std::filesystem::path(CONTACTNN_BINARY_DIR) / "test-search" / "c-header" / test;
  std::filesystem::create_directories(dir);
  return dir;
}

/// The C driver: every header included in one translation unit; for each case, reads "prefix_in.txt" (count,
/// then rows) and writes "prefix_out.txt": per query the one-query status and out, then the batch's.
std::string driver(const std::vector<Case>& cases) {
  std::string c = "#include <stdio.h>\n#include <stdlib.h>\n";
  for (const Case& k : cases) c += "#include \"" + k.prefix + ".h\"\n";
  for (const Case& k : cases) {
    const std::string n_raw = std::to_string(LocalSearch::raw_columns(k.model->surface()));
    c += "static int run_" + k.prefix +
         "(void) {\n"
         "  FILE* in = fopen(\"" +
         k.prefix +
         "_in.txt\", \"r\");\n"
         "  FILE* res = fopen(\"" +
         k.prefix +
         "_out.txt\", \"w\");\n"
         "  size_t n, i, k;\n  double *raw, *out;\n  int* status;\n"
         "  if (!in || !res || fscanf(in, \"%zu\", &n) != 1) return 1;\n"
         "  raw = malloc(n * " +
         n_raw +
         " * sizeof *raw);\n  out = malloc(2 * n * sizeof *out);\n"
         "  status = malloc(n * sizeof *status);\n"
         "  for (i = 0; i < n * " +
         n_raw +
         "; ++i) {\n"
         "    char word[64];\n    if (fscanf(in, \"%63s\", word) != 1) return 1;\n    raw[i] = strtod(word, "
         "NULL);\n  }\n"
         "  for (i = 0; i < 2 * n; ++i) out[i] = " +
         std::to_string(kUntouched) +
         ";\n"
         "  " +
         k.prefix +
         "_local_coordinates_batch(n, raw, out, status);\n"
         "  for (i = 0; i < n; ++i) {\n"
         "    double one[2] = {" +
         std::to_string(kUntouched) + ", " + std::to_string(kUntouched) +
         "};\n"
         "    const int s = " +
         k.prefix + "_local_coordinates(raw + i * " + n_raw +
         ", one);\n"
         "    fprintf(res, \"%d %.17g %.17g %d %.17g %.17g\\n\", s, one[0], one[1], status[i], out[2 * i], "
         "out[2 * i + 1]);\n"
         "  }\n"
         "  (void)k;\n  free(raw);\n  free(out);\n  free(status);\n  fclose(in);\n  return fclose(res) != "
         "0;\n}\n";
  }
  c += "int main(void) {\n  int failed = 0;\n";
  for (const Case& k : cases) c += "  failed |= run_" + k.prefix + "();\n";
  c += "  return failed;\n}\n";
  return c;
}

int expected_code(Status s) {
  switch (s) {
    case Status::kOk: return 0;
    case Status::kDegenerate:
    case Status::kInvalid: return 1;
    case Status::kOutOfDomain: return 2;
    default: return -1;
  }
}

/// Writes the headers, the driver and the inputs, compiles with `flags`, runs, and checks every case.
void compile_and_compare(const std::vector<Case>& cases, const std::string& flags, bool batch_bitwise) {
  const auto dir = work_dir(::testing::UnitTest::GetInstance()->current_test_info()->name());
  for (const Case& k : cases) {
    CHeaderOptions options;
    options.prefix = k.prefix;
    options.description = "test network " + k.prefix;
    std::ofstream(dir / (k.prefix + ".h")) << export_c_header(*k.model, options);
    std::ofstream in(dir / (k.prefix + "_in.txt"));
    in.precision(17);
    const auto stride = static_cast<std::size_t>(LocalSearch::raw_columns(k.model->surface()));
    in << k.raw.size() / stride << '\n';
    for (std::size_t i = 0; i < k.raw.size(); ++i) in << k.raw[i] << ((i + 1) % stride == 0 ? '\n' : ' ');
  }
  std::ofstream(dir / "driver.c") << driver(cases);
  const std::string compile = "cd \"" + dir.string() + "\" && \"" CONTACTNN_C_COMPILER "\" " + flags +
                              " -Wall -Wextra -pedantic -Werror -o driver driver.c -lm";
  ASSERT_EQ(std::system(compile.c_str()), 0) << compile;
  ASSERT_EQ(std::system(("cd \"" + dir.string() + "\" && ./driver").c_str()), 0);

  for (const Case& k : cases) {
    SCOPED_TRACE(k.prefix + " (" + flags + ")");
    const SurfaceKind kind = k.model->surface();
    const std::size_t n = k.raw.size() / static_cast<std::size_t>(LocalSearch::raw_columns(kind));
    std::vector<double> param(2 * n);
    std::vector<Status> status(n);
    LocalSearch(kind, Method::parse("network"), {}, k.model.get())
        .run(n, k.raw.data(), Results<double>{param.data(), nullptr, status.data(), nullptr}, 1);
    std::ifstream res(dir / (k.prefix + "_out.txt"));
    std::map<int, int> codes;
    for (std::size_t i = 0; i < n; ++i) {
      int one_status = -1, batch_status = -1;
      double one[2], batch[2];
      ASSERT_TRUE(res >> one_status >> one[0] >> one[1] >> batch_status >> batch[0] >> batch[1])
          << "query " << i;
      ASSERT_EQ(one_status, expected_code(status[i]))
          << "query " << i << ", library status " << to_string(status[i]);
      ASSERT_EQ(batch_status, one_status) << "query " << i;
      ++codes[one_status];
      for (int c = 0; c < 2; ++c) {
        if (one_status == 1) {
          EXPECT_EQ(one[c], kUntouched) << "query " << i;
          EXPECT_EQ(batch[c], kUntouched) << "query " << i;
          continue;
        }
        EXPECT_NEAR(one[c], param[2 * i + static_cast<std::size_t>(c)], k.tol)
            << "query " << i << " coordinate " << c;
        if (batch_bitwise) {
          EXPECT_EQ(batch[c], one[c]) << "query " << i << " coordinate " << c;
        } else {
          EXPECT_NEAR(batch[c], one[c], k.tol) << "query " << i;
        }
      }
    }
    EXPECT_GT(codes[0], static_cast<int>(n) / 2) << "most random paper-domain queries are inside the domain";
    EXPECT_GE(codes[1], 2) << "the degenerate and the NaN query";
    EXPECT_GE(codes[2], 1) << "the far slave";
  }
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  const auto& bilinear = shipped("bilinear-8.h5");
  const auto& gregory = shipped("gregory-48.h5");
  cases.push_back({"bilinear_8", std::make_shared<NetworkModel>(bilinear.network, bilinear.domain),
                   kFloatNetworkTol, queries(SurfaceKind::kBilinear, 1)});
  cases.push_back({"gregory_48", std::make_shared<NetworkModel>(gregory.network, gregory.domain),
                   kFloatNetworkTol, queries(SurfaceKind::kGregory, 2)});
  // Affine input features, a float and a deeper double network (the forward pass's other branches).
  cases.push_back(
      {"bilinear_affine",
       std::make_shared<NetworkModel>(random_network<float>(bilinear.domain, {9}, InputFeatures::kAffine, 3),
                                      bilinear.domain),
       kFloatNetworkTol, queries(SurfaceKind::kBilinear, 3)});
  cases.push_back(
      {"gregory_affine_deep",
       std::make_shared<NetworkModel>(
           random_network<double>(gregory.domain, {12, 7}, InputFeatures::kAffine, 4), gregory.domain),
       kDoubleNetworkTol, queries(SurfaceKind::kGregory, 4)});
  return cases;
}

TEST(ExportCHeader, HeadersShareOneTranslationUnitAndAgreeWithTheLibraryBatchBitForBit) {
  // ISO C: no contraction, so the vectorised batch and the one-query code round every operation alike.
  compile_and_compare(all_cases(), "-std=c99 -O3 -march=native -fno-math-errno -fno-trapping-math", true);
}

TEST(ExportCHeader, WithContractedMultiplyAddsTheBatchAgreesToRounding) {
  compile_and_compare(all_cases(), "-std=gnu99 -O2 -march=native -ffp-contract=fast", false);
}

TEST(ExportCHeader, HeadersCompileAsCxx11AndCxx17WithoutAWarning) {
  // FE codes in C++ include the header too: no designated initializers (C++20), no C-only construct.
  const auto dir = work_dir("cxx");
  std::string unit;
  for (const Case& k : all_cases()) {
    CHeaderOptions options;
    options.prefix = k.prefix;
    std::ofstream(dir / (k.prefix + ".h")) << export_c_header(*k.model, options);
    unit += "#include \"" + k.prefix + ".h\"\n";
  }
  unit +=
      "int main() {\n"
      "  double raw[27] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.3, 0.4, 0.2,\n"
      "                    0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};\n"
      "  double out[2];\n  int status[1];\n  bilinear_8_local_coordinates_batch(1, raw, out, status);\n"
      "  return gregory_48_local_coordinates(raw, out) + status[0];\n}\n";
  std::ofstream(dir / "unit.cpp") << unit;
  for (const char* standard : {"c++11", "c++17"}) {
    const std::string compile = "cd \"" + dir.string() +
                                "\" && \"" CONTACTNN_CXX_COMPILER "\" -std=" + standard +
                                " -O1 -Wall -Wextra -pedantic -Werror -o unit unit.cpp -lm";
    EXPECT_EQ(std::system(compile.c_str()), 0) << compile;
  }
}

TEST(ExportCHeader, EmbedsTheLibrarysKernelsVerbatim) {
  const auto& trained = shipped("bilinear-8.h5");
  const std::string header = export_c_header(NetworkModel(trained.network, trained.domain), {});
  EXPECT_NE(header.find(canonical_frame_source()), std::string::npos);
  EXPECT_NE(header.find(vector_sigmoid_source()), std::string::npos);
  // The whole text of canonical_frame.h, and only once.
  EXPECT_GT(canonical_frame_source().size(), 10000u);
  EXPECT_EQ(header.find(canonical_frame_source(), header.find(canonical_frame_source()) + 1),
            std::string::npos);
}

TEST(ExportCHeader, RejectsAPrefixThatIsNotACIdentifier) {
  const auto& trained = shipped("bilinear-8.h5");
  const NetworkModel model(trained.network, trained.domain);
  for (const char* bad : {"", "9lives", "a-b", "net.h"}) {
    CHeaderOptions o;
    o.prefix = bad;
    EXPECT_THROW((void)export_c_header(model, o), InvalidArgument) << bad;
  }
}

}  // namespace
}  // namespace contactnn::search
