#include "study/scene_pairs.hpp"

#include "geometry/bilinear_patch.hpp"
#include "io/csv.hpp"

namespace contactnn::study {

namespace {

/// An evaluation set of pairs (the reference's labels in the caller's order, as gen-configs --scene writes
/// them).
struct SetBuilder {
  eval::EvaluationSet set;
  std::vector<double> labels;
  SetBuilder(std::string name, std::string source, SurfaceKind kind) {
    set.name = std::move(name);
    set.source = std::move(source);
    set.surface = kind;
  }
  void add(const contact::NodeSegmentPair& p) {
    eval::append_raw(set.raw, p.config, set.surface);
    set.label_status.push_back(p.label.status);
    set.label_gap.push_back(p.label.gap);
    set.size.push_back(geometry::max_node_distance(p.config.nodes));
    set.label_iterations.push_back(p.label.iterations);
    labels.insert(labels.end(), {p.label.param[0], p.label.param[1]});
  }
  eval::EvaluationSet finish() {
    set.labels = Eigen::Map<const dataset::MatrixRM<double>>(labels.data(), set.rows(), 2);
    return std::move(set);
  }
};

/// The training data every size shares: the pattern draw, the scaling (from the training inputs alone, so

}  // namespace

contact::SearchOptions pairs_search_options(SurfaceKind surface) {
  contact::SearchOptions options;
  options.surface = surface;
  options.search = contact::GlobalSearchKind::kSurface;
  return options;
}

ScenePairs search_pairs(const contact::Scene& scene, SurfaceKind surface) {
  ScenePairs out;
  out.result = contact::search_scene(scene, pairs_search_options(surface));
  SetBuilder face("face-pairs", "the deck's pairs inside a face", surface);
  SetBuilder quad4("quad4-pairs", "the deck's pairs on quadrilaterals", surface);
  for (const contact::NodeSegmentPair& p : out.result.pairs) {
    if (p.status != contact::PairStatus::kFound) continue;
    ++out.locations[static_cast<std::size_t>(p.location)];
    if (scene.master.face_nodes(p.segment).type != mesh::FaceType::kQuad4) continue;
    ++out.quad4;
    quad4.add(p);
    if (p.location == Location::kFace) face.add(p);
  }
  out.face = face.finish();
  out.quad4_pairs = quad4.finish();
  return out;
}

std::string pairs_csv(const contact::Scene& scene, const ScenePairs& pairs, SurfaceKind surface) {
  const PairsCsvLayout layout{surface, false, true};
  std::string text;
  io::append_csv_row(text, pairs_csv_header(layout));
  for (const contact::NodeSegmentPair& p : pairs.result.pairs) append_pair_row(text, scene, p, layout);
  return text;
}

std::vector<std::string> pairs_csv_header(const PairsCsvLayout& layout) {
  std::vector<std::string> header;
  if (layout.increment) header.emplace_back("increment");
  for (const char* name : {"slave", "a", "b", "c", "d"}) header.emplace_back(name);
  for (auto name : kRawPointColumns) header.emplace_back(name);
  if (layout.surface == SurfaceKind::kGregory) {
    for (auto name : kRawNormalColumns) header.emplace_back(name);
  }
  const auto names = coordinate_names(layout.surface);
  for (const char* name : {names[0].data(), names[1].data(), "status", "gap", "iterations"})
    header.emplace_back(name);
  if (layout.surface_search) {
    for (const char* name : {"location", "px", "py", "pz", "face_type", "nodes"}) header.emplace_back(name);
  }
  return header;
}

std::vector<std::string> label_csv_fields(const dataset::Label& l) {
  const bool has_value = l.status == Status::kOk || l.status == Status::kOutside;
  // A result of zero is written 0, never -0 (x + 0.0 is +0 for x = -0 and x otherwise).
  const auto value = [&](double x) { return has_value ? io::format_double(x + 0.0) : std::string(); };
  return {value(l.param[0]), value(l.param[1]), std::string(to_string(l.status)), value(l.gap),
          l.status == Status::kNoSegment ? "" : std::to_string(l.iterations)};
}

void append_pair_row(std::string& text, const contact::Scene& scene, const contact::NodeSegmentPair& p,
                     const PairsCsvLayout& layout, int increment) {
  const bool gregory = layout.surface == SurfaceKind::kGregory;
  const std::size_t label_column =
      (layout.increment ? 6 : 5) + kRawPointColumns.size() + (gregory ? kRawNormalColumns.size() : 0);
  std::vector<std::string> row(label_column + 5 + (layout.surface_search ? 6 : 0));
  std::size_t c = 0;
  if (layout.increment) row[c++] = std::to_string(increment);
  row[c++] = std::to_string(p.slave_id);
  if (p.status == contact::PairStatus::kNoSegment) {
    row[label_column + 2] = "no_segment";
    io::append_csv_row(text, row);
    return;
  }
  // The nearest-node search pairs every slave with a segment by its 4 corners (SPEC 7), whatever its type.
  const mesh::FaceNodes face = scene.master.face_nodes(p.segment);
  if (!layout.surface_search || face.type == mesh::FaceType::kQuad4) {
    for (int n : p.nodes) row[c++] = std::to_string(scene.master.node_ids[static_cast<std::size_t>(n)]);
    for (const auto& x : p.config.nodes) {
      for (int k = 0; k < 3; ++k) row[c++] = io::format_double(x[k]);
    }
    for (int k = 0; k < 3; ++k) row[c++] = io::format_double(p.config.slave[k]);
    if (gregory) {
      for (const auto& n : p.config.normals) {
        for (int k = 0; k < 3; ++k) row[c++] = io::format_double(n[k]);
      }
    }
  }
  // SPEC 9: a face that is not a quad4 has no SPEC 7 configuration; its own local coordinates ((xi, eta) of
  // a quad8, (r, s) of a triangle, in the face's own node order) go in the coordinate columns.
  c = label_column;
  for (std::string& field : label_csv_fields(p.label)) row[c++] = std::move(field);
  if (layout.surface_search) {
    row[c++] = std::string(to_string(p.location));
    for (int k = 0; k < 3; ++k) row[c++] = io::format_double(p.point[k] + 0.0);
    row[c++] = std::string(mesh::to_string(face.type));
    std::string face_nodes;  // corners, then a quadratic face's mid-side nodes (SPEC 9)
    for (int n : face) {
      face_nodes += (face_nodes.empty() ? "" : " ") +
                    std::to_string(scene.master.node_ids[static_cast<std::size_t>(n)]);
    }
    row[c++] = std::move(face_nodes);
  }
  io::append_csv_row(text, row);
}

void keep_corner_slaves(contact::Scene& scene) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < scene.slave_ids.size(); ++i) {
    if (i < scene.slaves.midside.size() && scene.slaves.midside[i] != 0) continue;
    scene.slave_ids[kept] = scene.slave_ids[i];
    scene.slave_positions[kept] = scene.slave_positions[i];
    ++kept;
  }
  scene.slave_ids.resize(kept);
  scene.slave_positions.resize(kept);
  scene.slaves = mesh::corner_slaves(scene.slaves);
}

}  // namespace contactnn::study
