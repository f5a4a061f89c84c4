#include "history/run_states.hpp"

#include <algorithm>
#include <utility>

#include "core/error.hpp"

namespace contactnn::history {

RunStates::RunStates(mesh::ContactModel model, int pair, const io::FrdResults* results)
    : model_(std::move(model)), results_(results), scene_(contact::make_scene(model_, pair)) {
  current_ = count();
}

std::size_t RunStates::count() const { return results_ != nullptr ? results_->increments.size() : 0; }

const io::FrdIncrement& RunStates::increment(std::size_t i) const {
  CONTACTNN_REQUIRE_AS(InvalidArgument, i < count(),
                       "increment index " << i << " is out of range: the run holds " << count());
  return results_->increments[i];
}

const contact::Scene& RunStates::move_to(std::size_t i) {
  const io::FrdIncrement& inc = increment(i);
  if (rows_disp_nodes_ == nullptr || !std::ranges::equal(*rows_disp_nodes_, inc.disp_nodes)) {
    rows_ = io::node_rows(model_.mesh, *results_, i);  // throws before anything changes
    rows_disp_nodes_ = &inc.disp_nodes;
    ++lookups_;
  }
  const auto at = [&](int n) {
    return rows_.block[static_cast<std::size_t>(n)] >= 0 ? io::position_at(*results_, inc, rows_, n)
                                                         : model_.mesh.position(n);
  };
  const auto sector = static_cast<std::size_t>(scene_.sector_nodes);
  master_.resize(sector);
  for (std::size_t j = 0; j < sector; ++j) master_[j] = at(scene_.master.mesh_nodes[j]);
  slaves_.resize(scene_.slaves.nodes.size());
  for (std::size_t j = 0; j < slaves_.size(); ++j) slaves_[j] = at(scene_.slaves.nodes[j]);
  contact::move_scene(scene_, master_, slaves_);
  current_ = i;
  return scene_;
}

}  // namespace contactnn::history
