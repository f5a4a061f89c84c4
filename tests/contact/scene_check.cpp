// scene-check: the independent checks of gen-configs --scene on any deck (a tool for scripts/validate-scenes,
// not a ctest): for every contact pair and surface, the k-d tree global search against the brute-force one,
// and the labels against the dense-grid oracle of tests/test_support.hpp.
//
// Usage: scene-check DECK.inp [--grid N]
// Prints one line per pair and surface:
//   pair=K surface=S slaves=N found=N no_segment=N search_differences=N oracle_compared=N oracle_boundary=N
//   oracle_max_difference=X oracle_nearer=N
// Exit status: 0 when every check passes (no search difference, oracle difference within 1e-9 bilinear /
// 1e-8 Gregory, no oracle point nearer than a label), 1 otherwise, 3 for a deck that does not read.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "contact/scene.hpp"
#include "core/error.hpp"
#include "io/inp_deck.hpp"
#include "scene_checks.hpp"

int main(int argc, char** argv) {
  using namespace contactnn;
  if (argc < 2) {
    std::fprintf(stderr, "usage: scene-check DECK.inp [--grid N]\n");
    return 2;
  }
  int grid = 201;
  for (int i = 2; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--grid") grid = std::atoi(argv[i + 1]);
  }
  try {
    const mesh::ContactModel model = io::read_inp_deck(argv[1]);
    bool ok = true;
    std::printf("pairs=%zu\n", model.pairs.size());
    for (int k = 0; k < static_cast<int>(model.pairs.size()); ++k) {
      const contact::Scene scene = contact::make_scene(model, k);
      for (SurfaceKind kind : {SurfaceKind::kBilinear, SurfaceKind::kGregory}) {
        contact::SearchOptions options;
        options.surface = kind;
        options.search = contact::GlobalSearchKind::kNearestNode;
        const contact::SceneResult tree = contact::search_scene(scene, options);
        options.nearest = contact::NearestNodeMethod::kBruteForce;
        const contact::SceneResult brute = contact::search_scene(scene, options);
        const auto search = testing::compare_searches(tree.pairs, brute.pairs);
        const auto oracle = testing::compare_with_oracle(tree.pairs, kind, grid);
        const double tol = kind == SurfaceKind::kGregory ? 1e-8 : 1e-9;
        const bool pass =
            search.differences == 0 && oracle.max_difference <= tol && oracle.nearer_than_label == 0;
        ok = ok && pass;
        std::printf(
            "pair=%d surface=%s slaves=%zu found=%ld no_segment=%ld search_differences=%ld "
            "oracle_compared=%ld oracle_boundary=%ld oracle_max_difference=%.3g oracle_nearer=%ld %s\n",
            k, std::string(to_string(kind)).c_str(), tree.pairs.size(), tree.found, tree.no_segment,
            search.differences, oracle.compared, oracle.on_boundary, oracle.max_difference,
            oracle.nearer_than_label, pass ? "PASS" : "FAIL");
        if (search.differences > 0) std::printf("  first search difference: %s\n", search.first.c_str());
        if (oracle.max_difference > tol)
          std::printf("  worst oracle difference at slave %ld\n", oracle.worst_slave);
      }
    }
    return ok ? 0 : 1;
  } catch (const Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return e.exit_code();
  }
}
