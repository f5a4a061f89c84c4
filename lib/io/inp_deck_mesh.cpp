// The .inp deck reader's nodes, elements and sets (inp_deck_detail.hpp).
#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/inp_deck_detail.hpp"

namespace contactnn::io::detail {

namespace {

// A GENERATE line expanding to more ids than this is taken for a typo, not for a mesh.
constexpr long kMaxGeneratedIds = 100'000'000;

}  // namespace

long DeckReader::id_field(std::string_view field, std::size_t index, Location loc,
                          std::string_view what) const {
  long id = 0;
  if (!parse_id(field, id) || id <= 0) {
    fail(loc, keyword_,
         "field " + std::to_string(index + 1) + ": " + quote_text(field) + " is not a " + std::string(what) +
             " (a positive integer)");
  }
  return id;
}

void DeckReader::node_line(std::string_view line, Location loc) {
  const std::vector<std::string_view> f = split_fields(line);
  const long id = id_field(f[0], 0, loc, "node id");
  if (f.size() < 2) fail(loc, keyword_, "node " + std::to_string(id) + " has no coordinates");
  mesh::Vec3 x = mesh::Vec3::Zero();
  for (std::size_t k = 1; k < f.size() && k <= 3; ++k) {
    if (f[k].empty()) continue;  // a blank coordinate is 0, as in Abaqus
    double value = 0.0;
    if (!parse_coordinate(f[k], value)) {
      fail(loc, keyword_,
           "node " + std::to_string(id) + ": field " + std::to_string(k + 1) + ": " + quote_text(f[k]) +
               " is not a finite number");
    }
    x[static_cast<Eigen::Index>(k - 1)] = value;
  }
  const int existing = model_.mesh.find_node(id);
  if (existing >= 0) {
    if (model_.mesh.position(existing) != x) {
      fail(loc, keyword_,
           "node " + std::to_string(id) + " is defined again with other coordinates (first at " +
               where(node_where_[static_cast<std::size_t>(existing)]) + ")");
    }
  } else {
    model_.mesh.add_node(id, x);
    node_where_.push_back(loc);
  }
  if (!target_set_.empty()) nsets_[target_set_].ids.push_back(id);
}

int DeckReader::type_index(const std::string& name) {
  const mesh::ElementType type = mesh::element_type(name);
  for (std::size_t i = 0; i < types_.size(); ++i) {
    if (types_[i].name == type.name) return static_cast<int>(i);
  }
  types_.push_back(type);
  return static_cast<int>(types_.size() - 1);
}

void DeckReader::element_line(std::string_view line, Location loc) {
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  if (f.empty()) return;
  std::size_t first = 0;
  if (!element_open_) {
    current_ = {};
    current_.id = id_field(f[0], 0, loc, "element id");
    current_.type = element_type_;
    current_.begin = current_.end = element_node_ids_.size();
    current_.where = loc;
    element_open_ = true;
    first = 1;
  }
  for (std::size_t i = first; i < f.size(); ++i) {
    element_node_ids_.push_back(id_field(f[i], i, loc, "node id"));
    ++current_.end;
  }
  const mesh::ElementType& type = types_[static_cast<std::size_t>(current_.type)];
  const auto count = static_cast<int>(current_.end - current_.begin);
  if (type.node_count > 0) {
    if (count > type.node_count) {
      fail(loc, keyword_,
           "element " + std::to_string(current_.id) + " (" + type.name + ") has " + std::to_string(count) +
               " node ids, expected " + std::to_string(type.node_count));
    }
    if (count == type.node_count) finish_element(false);
  } else if (line.back() != ',') {
    finish_element(false);
  }
}

/// Closes the open element. At a keyword (`at_keyword`), an element still short of nodes is an error.
void DeckReader::finish_element(bool at_keyword) {
  if (!element_open_) return;
  element_open_ = false;
  const mesh::ElementType& type = types_[static_cast<std::size_t>(current_.type)];
  const auto count = static_cast<int>(current_.end - current_.begin);
  if (at_keyword && type.node_count > 0 && count < type.node_count) {
    fail(current_.where, "*ELEMENT",
         "element " + std::to_string(current_.id) + " (" + type.name + ") has " + std::to_string(count) +
             " node ids before the next keyword, expected " + std::to_string(type.node_count));
  }
  if (count == 0)
    fail(current_.where, "*ELEMENT", "element " + std::to_string(current_.id) + " has no nodes");
  const auto [it, inserted] = element_by_id_.emplace(current_.id, elements_.size());
  if (!inserted) {
    const PendingElement& old = elements_[it->second];
    const bool same = old.type == current_.type && old.end - old.begin == current_.end - current_.begin &&
                      std::equal(element_node_ids_.begin() + static_cast<long>(old.begin),
                                 element_node_ids_.begin() + static_cast<long>(old.end),
                                 element_node_ids_.begin() + static_cast<long>(current_.begin));
    if (!same) {
      fail(current_.where, "*ELEMENT",
           "element " + std::to_string(current_.id) + " is defined again differently (first at " +
               where(old.where) + ")");
    }
    element_node_ids_.resize(current_.begin);
  } else {
    elements_.push_back(current_);
  }
  if (!target_set_.empty()) elsets_[target_set_].ids.push_back(current_.id);
}

std::string DeckReader::define_set(std::unordered_map<std::string, NamedSet>& sets, const std::string& name,
                                   Location loc) {
  std::string key = upper(trim(name));
  auto [it, inserted] = sets.try_emplace(key);
  if (inserted) it->second = {std::string(trim(name)), {}, loc};
  return key;
}

void DeckReader::set_line(std::unordered_map<std::string, NamedSet>& sets, std::string_view kind,
                          std::string_view line, Location loc) {
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  std::vector<long>& ids = sets[target_set_].ids;
  if (generate_) {
    if (f.size() < 2 || f.size() > 3) {
      fail(loc, keyword_,
           "GENERATE needs 'first, last[, increment]', got " + std::to_string(f.size()) + " fields");
    }
    const long first = id_field(f[0], 0, loc, std::string(kind) + " id");
    const long last = id_field(f[1], 1, loc, std::string(kind) + " id");
    const long step = f.size() == 3 ? id_field(f[2], 2, loc, "increment") : 1;
    if (last < first || (last - first) / step >= kMaxGeneratedIds) {
      fail(loc, keyword_,
           "GENERATE range " + std::to_string(first) + ".." + std::to_string(last) + " step " +
               std::to_string(step) + " is empty or too long");
    }
    for (long id = first; id <= last; id += step) ids.push_back(id);
    return;
  }
  for (std::size_t i = 0; i < f.size(); ++i) {
    long id = 0;
    if (parse_id(f[i], id)) {
      if (id <= 0) id_field(f[i], i, loc, std::string(kind) + " id");
      ids.push_back(id);
      continue;
    }
    const auto it = sets.find(upper(f[i]));
    if (it == sets.end()) {
      fail(loc, keyword_,
           "field " + std::to_string(i + 1) + ": unknown " + std::string(kind) + " set " + quote_text(f[i]));
    }
    const std::vector<long> copy = it->second.ids;  // the set may be the one being extended
    ids.insert(ids.end(), copy.begin(), copy.end());
  }
}

void DeckReader::nodes_of_element_set(const std::string& elset, Location loc) {
  const auto it = elsets_.find(upper(trim(elset)));
  if (it == elsets_.end()) fail(loc, keyword_, "ELSET=" + quote_text(elset) + ": unknown element set");
  std::vector<long>& ids = nsets_[target_set_].ids;
  for (long e : it->second.ids) {
    const auto el = element_by_id_.find(e);
    if (el == element_by_id_.end()) {
      fail(loc, keyword_,
           "ELSET=" + quote_text(elset) + " holds element " + std::to_string(e) + ", which is not defined");
    }
    const PendingElement& p = elements_[el->second];
    ids.insert(ids.end(), element_node_ids_.begin() + static_cast<long>(p.begin),
               element_node_ids_.begin() + static_cast<long>(p.end));
  }
}

}  // namespace contactnn::io::detail
