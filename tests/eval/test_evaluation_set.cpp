// Tests of lib/eval/evaluation_set: queries and reference labels from datasets and labelled RAW.csv files.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "dataset/labeller.hpp"
#include "dataset/sampling.hpp"
#include "eval/evaluation_set.hpp"
#include "geometry/affine_frame.hpp"
#include "test_support.hpp"

namespace contactnn::eval {
namespace {

dataset::LabelledSet small_random_set(SurfaceKind kind) {
  dataset::EnumerationOptions o;
  o.surface = kind;
  if (kind == SurfaceKind::kGregory) {
    o.filters.min_angle_degrees = 60;
    o.filters.max_angle_degrees = 120;
  }
  dataset::EnumerationSummary summary;
  return dataset::sample_configurations(o, 50, summary);
}

TEST(EvaluationSet, DatasetRowsPlacedAtRandomKeepTheirLabelsAndScaleTheirGaps) {
  for (const SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
    const dataset::LabelledSet set = small_random_set(kind);
    const EvaluationSet placed = set_from_dataset(set, "s", "s.h5", true, 4);
    ASSERT_EQ(placed.rows(), set.size());
    const int cols = EvaluationSet::raw_columns(kind);
    ASSERT_EQ(placed.raw.size(), static_cast<std::size_t>(cols * set.size()));
    for (Eigen::Index r = 0; r < set.size(); ++r) {
      // The world query, labelled afresh by the reference, is the dataset's row (an independent route: the
      // labeller from world coordinates, in the caller's order).
      const double* q = &placed.raw[static_cast<std::size_t>(r * cols)];
      geometry::Configuration c{};
      for (int i = 0; i < 4; ++i) c.nodes[i] = geometry::Vec3(q[3 * i], q[3 * i + 1], q[3 * i + 2]);
      c.slave = geometry::Vec3(q[12], q[13], q[14]);
      for (int i = 0; i < 4 && kind == SurfaceKind::kGregory; ++i) {
        c.normals[i] = geometry::Vec3(q[15 + 3 * i], q[16 + 3 * i], q[17 + 3 * i]);
      }
      const dataset::Label l = dataset::label_configuration(c, kind);
      ASSERT_EQ(l.status, Status::kOk);
      EXPECT_NEAR(l.param[0], placed.labels(r, 0), 1e-9);
      EXPECT_NEAR(l.param[1], placed.labels(r, 1), 1e-9);
      EXPECT_NEAR(l.gap / placed.size[static_cast<std::size_t>(r)],
                  placed.label_gap[static_cast<std::size_t>(r)] / placed.size[static_cast<std::size_t>(r)],
                  1e-9);
      EXPECT_EQ(placed.label_iterations[static_cast<std::size_t>(r)], set.iterations[r]);
    }
  }
}

TEST(EvaluationSet, LabelledCsvGivesQueriesLabelsAndSkipsRowsWithoutASegment) {
  const auto dir = testing::test_output_dir("test-eval") / "labelled-csv";
  std::filesystem::create_directories(dir);
  const std::string header =
      "slave,ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz,xi,eta,status,gap,iterations\n";
  std::ofstream(dir / "pairs.csv") << header << "1,0,0,0,2,0,0,2,1,0,0,1,0,0.5,0.25,0.1,-0.5,-0.5,ok,0.1,3\n"
                                   << "2,,,,,,,,,,,,,,,,,,no_segment,,\n"
                                   << "3,0,0,0,2,0,0,2,1,0,0,1,0,3,0.5,0,2,0,outside,0,4\n";
  const EvaluationSet s = set_from_labelled_csv(dir / "pairs.csv", SurfaceKind::kBilinear);
  ASSERT_EQ(s.rows(), 2);
  EXPECT_EQ(s.skipped_no_segment, 1);
  EXPECT_EQ(s.labels(0, 0), -0.5);
  EXPECT_EQ(s.labels(1, 0), 2.0);
  EXPECT_EQ(s.label_status[1], Status::kOutside);
  EXPECT_EQ(s.label_gap[0], 0.1);
  EXPECT_DOUBLE_EQ(s.size[0], std::sqrt(5.0));  // the diagonal of the 2 x 1 rectangle
  EXPECT_EQ(s.raw[13], 0.25);                   // sy of the first query
  std::ofstream(dir / "bad.csv") << header << "1,0,0,0,2,0,0,2,1,0,0,1,0,0.5,0.25,0.1,-0.5,-0.5,fine,0.1,3\n";
  try {
    (void)set_from_labelled_csv(dir / "bad.csv", SurfaceKind::kBilinear);
    FAIL() << "an unknown status was accepted";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv':2: column 'status': 'fine' is not a status"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir / "unlabelled.csv")
      << "ax,ay,az,bx,by,bz,cx,cy,cz,dx,dy,dz,sx,sy,sz\n0,0,0,1,0,0,1,1,0,0,1,0,0.5,0.5,1\n";
  EXPECT_THROW((void)set_from_labelled_csv(dir / "unlabelled.csv", SurfaceKind::kBilinear), FormatError);
}

}  // namespace
}  // namespace contactnn::eval
