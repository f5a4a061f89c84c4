#include "mlp/export_c_header.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "geometry/affine_frame.hpp"
#include "mlp/random.hpp"

namespace contactnn::mlp {
namespace {

// The header computes the forward pass in float with expf and sequential sums; the library uses Eigen's
// rational logistic and SIMD sums. Both round at ~1e-7 relative per operation; through ~20 terms and the
// output scaling (x 2.5) that stays below 2e-6, so 2e-5 leaves a margin and still catches any wrong
// weight, scaling or frame step (each of which moves results by >= 1e-3).
constexpr double kHeaderTolerance = 2e-5;
// The normalisation is the same double arithmetic in C and C++ up to FMA contraction: ~1e-15 per step.
constexpr double kFeatureTolerance = 1e-12;

std::filesystem::path temp_dir() {
  const auto dir = std::filesystem::path(CONTACTNN_BINARY_DIR) / "test-mlp" / "header";
  std::filesystem::create_directories(dir);
  return dir;
}

using geometry::Vec3;

Vec3 random_unit(Rng& rng) {
  for (;;) {
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (v.norm() > 0.1 && v.norm() <= 1.0) return v.normalized();
  }
}

// A configuration in the paper's normalised ranges, moved to a random position, orientation and scale.
geometry::Configuration random_world(Rng& rng, bool gregory) {
  geometry::Configuration local;
  local.nodes[0] = Vec3::Zero();
  local.nodes[1] = Vec3(1, 0, 0);
  local.nodes[2] = Vec3(rng.uniform(0.5, 1.8), rng.uniform(0.5, 1.8), rng.uniform(-0.3, 0.3));
  local.nodes[3] = Vec3(rng.uniform(-0.6, 0.6), rng.uniform(0.3, 0.8), 0.0);
  local.slave = Vec3(rng.uniform(-0.5, 1.5), rng.uniform(-0.5, 1.5), rng.uniform(-0.3, 0.3));
  for (auto& n : local.normals) n = (Vec3(0, 0, 1) + 0.15 * random_unit(rng)) * rng.uniform(0.5, 3.0);
  const Eigen::Matrix3d rotation = Eigen::Quaterniond(Eigen::Vector4d(rng.uniform(-1, 1), rng.uniform(-1, 1),
                                                                      rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized())
                                       .toRotationMatrix();
  const double scale = rng.uniform(0.01, 100.0);
  const Vec3 shift(rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-50, 50));
  // The caller's node order is any of the 8 (the header must bring it to the canonical one itself).
  const SquareSymmetry order = all_square_symmetries()[static_cast<std::size_t>(rng.uniform(0.0, 8.0)) % 8];
  geometry::Configuration world;
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(order.caller_node(i));
    world.nodes[k] = shift + scale * (rotation * local.nodes[i]);
    world.normals[k] = rotation * local.normals[i];
  }
  world.slave = shift + scale * (rotation * local.slave);
  (void)gregory;
  return world;
}

struct Expected {
  int status = 0;
  double out[2] = {0, 0};
  std::array<double, 16> features{};
};

template <class Real>
Expected library_result(const Network<Real>& net, const CHeaderOptions& options, const geometry::Configuration& c) {
  Expected e;
  const auto n = geometry::normalise(c, options.surface);
  if (!n.value) {
    e.status = 1;
    return e;
  }
  e.features = n.value->features;
  ForwardPass<Real> pass(net);
  predict(net, n.value->features.data(), e.out, pass);
  const auto caller = n.value->to_caller({e.out[0], e.out[1]}, options.surface);
  e.out[0] = caller[0];
  e.out[1] = caller[1];
  for (int i = 0; i < net.input_count(); ++i) {
    if (e.features[i] < options.domain_min[i] - 1e-9 * (options.domain_max[i] - options.domain_min[i]) ||
        e.features[i] > options.domain_max[i] + 1e-9 * (options.domain_max[i] - options.domain_min[i])) {
      e.status = 2;
    }
  }
  return e;
}

template <class Real>
void check_header(SurfaceKind surface, std::vector<int> hidden, const std::string& prefix,
                  InputFeatures input_features = InputFeatures::kPaper) {
  const bool gregory = surface == SurfaceKind::kGregory;
  const int n_in = feature_count(surface);
  Scaling s;
  s.input_min.assign(n_in, -1.0);
  s.input_max.assign(n_in, 1.0);
  s.input_min[1] = -2.0;
  s.input_max[1] = 2.0;
  s.input_max[4] = s.input_min[4];  // a constant input: gain 0
  s.input_features = input_features;
  const ParamDomain range = param_domain(surface);
  s.output_min.assign(2, range.lo);
  s.output_max.assign(2, range.hi);
  std::vector<int> sizes{n_in};
  sizes.insert(sizes.end(), hidden.begin(), hidden.end());
  sizes.push_back(2);
  Network<Real> net(sizes, 1.7, s);
  net.initialize(31);
  CHeaderOptions options;
  options.prefix = prefix;
  options.surface = surface;
  options.domain_min.assign(n_in, -2.5);
  options.domain_max.assign(n_in, 2.5);
  options.domain_max[0] = 1.2;  // narrow enough that some random configurations fall outside
  options.description = "test network";
  const std::string header = export_c_header(net, options);

  const auto dir = temp_dir();
  std::ofstream(dir / (prefix + ".h")) << header;
  const int n_raw = gregory ? 27 : 15;
  std::ofstream(dir / (prefix + "_driver.c"))
      << "#include <stdio.h>\n#include \"" << prefix << ".h\"\n"
      << "int main(void) {\n  double raw[" << n_raw << "], out[2];\n  int i;\n"
      << "  for (;;) {\n    for (i = 0; i < " << n_raw << "; ++i) if (scanf(\"%lf\", &raw[i]) != 1) return 0;\n"
      << "    out[0] = out[1] = 0.0;\n"
      << "    {\n      double f[" << n_in << "];\n      int rot[8], mir[8], zt = 0, n = " << prefix << "_symmetries(raw, rot, mir), fs = n > 0 ? " << prefix << "_features(raw, rot[0], mir[0], 0, f, &zt) : 1;\n"
      << "      int s = " << prefix << "_local_coordinates(raw, out);\n"
      << "      printf(\"%d %.17g %.17g\", s, out[0], out[1]);\n"
      << "      for (i = 0; i < " << n_in << "; ++i) printf(\" %.17g\", fs == 0 ? f[i] : 0.0);\n"
      << "      printf(\"\\n\");\n    }\n  }\n}\n";

  Rng rng(gregory ? 8 : 9);
  std::vector<geometry::Configuration> configs;
  for (int k = 0; k < 300; ++k) configs.push_back(random_world(rng, gregory));
  geometry::Configuration degenerate = configs[0];
  degenerate.nodes[1] = degenerate.nodes[0];  // A = B
  configs.push_back(degenerate);
  {
    std::ofstream in(dir / (prefix + "_in.txt"));
    in.precision(17);
    for (const auto& c : configs) {
      for (int i = 0; i < 4; ++i) in << c.nodes[i].x() << ' ' << c.nodes[i].y() << ' ' << c.nodes[i].z() << ' ';
      in << c.slave.x() << ' ' << c.slave.y() << ' ' << c.slave.z();
      if (gregory) {
        for (int i = 0; i < 4; ++i) in << ' ' << c.normals[i].x() << ' ' << c.normals[i].y() << ' ' << c.normals[i].z();
      }
      in << '\n';
    }
  }
  const std::string exe = (dir / (prefix + "_driver")).string();
  const std::string compile = std::string("\"") + CONTACTNN_C_COMPILER + "\" -std=c99 -O2 -Wall -Wextra -pedantic -Werror -o \"" +
                              exe + "\" \"" + (dir / (prefix + "_driver.c")).string() + "\" -lm";
  ASSERT_EQ(std::system(compile.c_str()), 0) << compile;
  const std::string run = "\"" + exe + "\" < \"" + (dir / (prefix + "_in.txt")).string() + "\" > \"" +
                          (dir / (prefix + "_out.txt")).string() + "\"";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;

  std::ifstream out(dir / (prefix + "_out.txt"));
  int outside = 0;
  for (std::size_t k = 0; k < configs.size(); ++k) {
    int status = -1;
    double xi = 0, eta = 0;
    ASSERT_TRUE(out >> status >> xi >> eta) << "row " << k;
    std::array<double, 16> f{};
    for (int i = 0; i < n_in; ++i) out >> f[i];
    const Expected e = library_result(net, options, configs[k]);
    ASSERT_EQ(status, e.status) << "row " << k;
    outside += status == 2;
    if (status == 1) continue;
    for (int i = 0; i < n_in; ++i) EXPECT_NEAR(f[i], e.features[i], kFeatureTolerance) << "row " << k << " feature " << i;
    EXPECT_NEAR(xi, e.out[0], kHeaderTolerance) << "row " << k;
    EXPECT_NEAR(eta, e.out[1], kHeaderTolerance) << "row " << k;
  }
  EXPECT_GT(outside, 0) << "no configuration exercised the domain check";
  EXPECT_LT(outside, static_cast<int>(configs.size()) - 1) << "every configuration was outside the domain";
}

TEST(ExportCHeader, BilinearHeaderCompilesAndAgreesWithLibrary) {
  check_header<float>(SurfaceKind::kBilinear, {8}, "bilinear_8");
}

TEST(ExportCHeader, AffineInputHeadersAgreeWithLibrary) {
  check_header<float>(SurfaceKind::kBilinear, {8}, "bilinear_affine", InputFeatures::kAffine);
  check_header<double>(SurfaceKind::kGregory, {6}, "gregory_affine", InputFeatures::kAffine);
}

TEST(ExportCHeader, GregoryDeepDoubleHeaderCompilesAndAgreesWithLibrary) {
  check_header<double>(SurfaceKind::kGregory, {12, 7}, "gregory_deep");
}

TEST(ExportCHeader, RejectsMismatchedNetworkOrBadPrefix) {
  Scaling s;
  s.input_min.assign(3, -1.0);
  s.input_max.assign(3, 1.0);
  s.output_min.assign(2, -1.0);
  s.output_max.assign(2, 1.0);
  const Network<float> net({3, 4, 2}, 2.0, s);
  CHeaderOptions o;
  EXPECT_THROW((void)export_c_header(net, o), InvalidArgument);
  o.prefix = "9bad";
  EXPECT_THROW((void)export_c_header(net, o), InvalidArgument);
}

}  // namespace
}  // namespace contactnn::mlp
