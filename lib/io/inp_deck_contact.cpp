// The .inp deck reader's surfaces, contact pairs and cyclic symmetry, and the resolution of the names they
// use (inp_deck_detail.hpp).
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "io/inp_deck_detail.hpp"

namespace contactnn::io::detail {

int DeckReader::define_surface(const std::string& raw_name, const std::string& type_text, Location loc) {
  const std::string type_key = keyword_form(type_text);
  mesh::SurfaceType type = mesh::SurfaceType::kUnsupported;
  if (type_key == "ELEMENT") type = mesh::SurfaceType::kElement;
  if (type_key == "NODE") type = mesh::SurfaceType::kNode;
  const std::string name(trim(raw_name));
  const std::string key = upper(name) + "\n" + (type == mesh::SurfaceType::kUnsupported ? "OTHER" : type_key);
  const auto [it, inserted] = surface_by_key_.emplace(key, static_cast<int>(surfaces_.size()));
  if (inserted) surfaces_.push_back({name, type, type_text, {}, loc});
  return it->second;
}

void DeckReader::surface_line(std::string_view line, Location loc) {
  PendingSurface& s = surfaces_[static_cast<std::size_t>(surface_)];
  if (s.type == mesh::SurfaceType::kUnsupported) return;
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  if (f.empty()) return;
  SurfaceEntry entry{std::string(f[0]), 0, loc};
  if (s.type == mesh::SurfaceType::kElement) {
    if (f.size() < 2) {
      fail(loc, keyword_,
           "surface " + quote_text(s.name) + ": " + quote_text(f[0]) +
               " needs a face label (S1..S6) in field 2");
    }
    entry.face = parse_face_label(f[1]);
    if (entry.face == 0) {
      fail(loc, keyword_,
           "surface " + quote_text(s.name) + ": field 2: " + quote_text(f[1]) +
               " is not a face label (S1..S6)");
    }
  }
  s.entries.push_back(std::move(entry));
}

void DeckReader::pair_line(std::string_view line, Location loc) {
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  if (f.size() != 2) {
    fail(loc, keyword_,
         "expected 'slave surface, master surface', got " + std::to_string(f.size()) + " fields");
  }
  pairs_.push_back({std::string(f[0]), std::string(f[1]), node_to_surface_, loc});
}

void DeckReader::tie_line(std::string_view line, Location loc) {
  PendingTie& tie = ties_.back();
  if (!tie.dependent.empty()) fail(loc, keyword_, "tie " + quote_text(tie.name) + " has a second data line");
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  if (f.size() != 2) {
    fail(loc, keyword_,
         "expected 'dependent surface, independent surface', got " + std::to_string(f.size()) + " fields");
  }
  tie.dependent = std::string(f[0]);
  tie.independent = std::string(f[1]);
}

void DeckReader::cyclic_line(std::string_view line, Location loc) {
  PendingCyclic& c = cyclic_.back();
  if (c.has_axis) fail(loc, keyword_, "a second data line (the axis is one line: ax, ay, az, bx, by, bz)");
  const std::vector<std::string_view> f = non_empty(split_fields(line));
  if (f.size() != 6) {
    fail(loc, keyword_,
         "expected the axis 'ax, ay, az, bx, by, bz', got " + std::to_string(f.size()) + " fields");
  }
  for (std::size_t k = 0; k < 6; ++k) {
    if (!parse_coordinate(f[k], c.axis[k])) {
      fail(loc, keyword_,
           "field " + std::to_string(k + 1) + ": " + quote_text(f[k]) + " is not a finite number");
    }
  }
  const mesh::Vec3 a(c.axis[0], c.axis[1], c.axis[2]), b(c.axis[3], c.axis[4], c.axis[5]);
  if (!((b - a).norm() > 0.0)) fail(loc, keyword_, "the axis points a and b coincide");
  c.has_axis = true;
}

void DeckReader::resolve_cyclic() {
  std::vector<const PendingTie*> cyclic_ties;
  for (const PendingTie& t : ties_) {
    if (t.dependent.empty())
      fail(t.where, "*TIE", "tie " + quote_text(t.name) + " has no 'dependent, independent' line");
    cyclic_ties.push_back(&t);
  }
  for (const PendingCyclic& c : cyclic_) {
    if (!c.has_axis) fail(c.where, "*CYCLIC SYMMETRY MODEL", "no axis line (ax, ay, az, bx, by, bz)");
    const PendingTie* tie = nullptr;
    if (c.tie.empty()) {
      if (cyclic_ties.size() != 1) {
        fail(c.where, "*CYCLIC SYMMETRY MODEL",
             "TIE= is needed: the deck has " + std::to_string(cyclic_ties.size()) +
                 " *TIE, CYCLIC SYMMETRY cards");
      }
      tie = cyclic_ties.front();
    } else {
      for (const PendingTie* t : cyclic_ties) {
        if (upper(trim(t->name)) == upper(trim(c.tie))) tie = t;
      }
      if (tie == nullptr) {
        fail(c.where, "*CYCLIC SYMMETRY MODEL",
             "TIE=" + quote_text(c.tie) + ": no *TIE, CYCLIC SYMMETRY of that name");
      }
    }
    mesh::CyclicSymmetry s;
    s.sectors = c.sectors;
    s.axis_a = mesh::Vec3(c.axis[0], c.axis[1], c.axis[2]);
    s.axis_b = mesh::Vec3(c.axis[3], c.axis[4], c.axis[5]);
    s.tie = tie->name;
    s.dependent = tie->dependent;
    s.independent = tie->independent;
    s.where = where(c.where);
    model_.cyclic.push_back(std::move(s));
  }
}

mesh::ContactModel DeckReader::resolve() {
  mesh::SolidMesh& mesh = model_.mesh;
  std::vector<int> nodes;
  for (const PendingElement& e : elements_) {
    nodes.clear();
    for (std::size_t i = e.begin; i < e.end; ++i) {
      const int n = mesh.find_node(element_node_ids_[i]);
      if (n < 0) {
        fail(e.where, "*ELEMENT",
             "element " + std::to_string(e.id) + ": node " + std::to_string(element_node_ids_[i]) +
                 " (node " + std::to_string(i - e.begin + 1) + " of the element) is not defined");
      }
      nodes.push_back(n);
    }
    mesh.add_element(e.id, types_[static_cast<std::size_t>(e.type)], nodes);
  }
  for (const PendingSurface& s : surfaces_) model_.surfaces.push_back(resolve_surface(s));
  resolve_cyclic();
  for (const PendingPair& p : pairs_) {
    mesh::ContactPairDefinition pair;
    pair.slave_name = p.slave;
    pair.master_name = p.master;
    pair.node_to_surface = p.node_to_surface;
    pair.where = where(p.where);
    const int slave_node = find_surface(p.slave, "NODE");
    const int slave_element = find_surface(p.slave, "ELEMENT");
    const int master_element = find_surface(p.master, "ELEMENT");
    const int master_node = find_surface(p.master, "NODE");
    pair.slave = p.node_to_surface && slave_node >= 0 ? slave_node
                 : slave_element >= 0                 ? slave_element
                 : slave_node >= 0                    ? slave_node
                                                      : find_surface(p.slave, "OTHER");
    pair.master = master_element >= 0 ? master_element
                  : master_node >= 0  ? master_node
                                      : find_surface(p.master, "OTHER");
    if (pair.slave < 0)
      fail(p.where, "*CONTACT PAIR", "unknown slave surface " + quote_text(p.slave) + " (field 1)");
    if (pair.master < 0)
      fail(p.where, "*CONTACT PAIR", "unknown master surface " + quote_text(p.master) + " (field 2)");
    model_.pairs.push_back(std::move(pair));
  }
  return std::move(model_);
}

int DeckReader::find_surface(const std::string& name, const std::string& type) const {
  const auto it = surface_by_key_.find(upper(trim(name)) + "\n" + type);
  return it == surface_by_key_.end() ? -1 : it->second;
}

mesh::SurfaceDefinition DeckReader::resolve_surface(const PendingSurface& s) const {
  mesh::SurfaceDefinition out;
  out.name = s.name;
  out.type = s.type;
  out.type_text = s.type_text;
  out.where = where(s.where);
  const mesh::SolidMesh& mesh = model_.mesh;
  for (const SurfaceEntry& entry : s.entries) {
    const std::string context = "surface " + quote_text(s.name);
    std::vector<long> ids;
    std::string from_set;
    long id = 0;
    if (parse_id(entry.reference, id)) {
      ids.push_back(id);
    } else {
      const auto& sets = s.type == mesh::SurfaceType::kNode ? nsets_ : elsets_;
      const auto it = sets.find(upper(entry.reference));
      if (it == sets.end()) {
        fail(entry.where, "*SURFACE",
             context + ": field 1: unknown " + (s.type == mesh::SurfaceType::kNode ? "node" : "element") +
                 " set " + quote_text(entry.reference));
      }
      ids = it->second.ids;
      from_set = " (in set " + quote_text(it->second.name) + ", " + where(it->second.where) + ")";
    }
    for (long i : ids) {
      if (s.type == mesh::SurfaceType::kNode) {
        const int n = mesh.find_node(i);
        if (n < 0)
          fail(entry.where, "*SURFACE",
               context + ": node " + std::to_string(i) + from_set + " is not defined");
        out.nodes.push_back(n);
        continue;
      }
      const int e = mesh.find_element(i);
      if (e < 0)
        fail(entry.where, "*SURFACE",
             context + ": element " + std::to_string(i) + from_set + " is not defined");
      const mesh::ElementType& type = mesh.element_type(e);
      const bool shell_label = entry.face < 0;
      if (type.face_count > 0 && (shell_label || entry.face > type.face_count)) {
        fail(entry.where, "*SURFACE",
             context + ": element " + std::to_string(i) + from_set + " is a " + type.name +
                 ", whose faces are S1..S" + std::to_string(type.face_count) + "; the face label says " +
                 (shell_label ? std::string(entry.face == -1 ? "SPOS" : "SNEG")
                              : "S" + std::to_string(entry.face)));
      }
      out.faces.push_back({e, entry.face});
    }
  }
  return out;
}

}  // namespace contactnn::io::detail
