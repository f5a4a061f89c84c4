// The Python module contactnn (issue 42; docs/python.md): lib/search's local searches, the contact search
// handle (contact::ContactSearch), a deck's contact pair and a CalculiX run's increments, and network files,
// with numpy arrays in and out.
//
// Arrays. An input of float64 or float32 that is C-contiguous is read where it lies (no copy): anything else
// is refused with a message saying what was expected, never converted behind the caller's back (a list or
// tuple is taken as np.asarray takes it). Outputs are allocated, or given with `out=` (checked the same way,
// and writable). The GIL is released while a search runs. contactnn::Error becomes the module's exception of
// the same name: InvalidArgument a ValueError, FormatError a ValueError, IoError an OSError, NumericalError
// an ArithmeticError, each also a contactnn.Error carrying the library's message and `exit_code`
// (docs/tools.md's codes).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "contact/contact_search.hpp"
#include "contact/scene.hpp"
#include "core/conventions.hpp"
#include "core/error.hpp"
#include "core/input_features.hpp"
#include "io/face_network_file.hpp"
#include "io/frd_results.hpp"
#include "io/inp_deck.hpp"
#include "io/network_file.hpp"
#include "io/network_model_file.hpp"
#include "mlp/network.hpp"
#include "search/face_network.hpp"
#include "search/face_search.hpp"
#include "search/local_search.hpp"
#include "search/method.hpp"
#include "search/network_model.hpp"

namespace py = pybind11;

namespace contactnn::python {
namespace {

// ---------------------------------------------------------------------------------------------------------------
// Exceptions.

struct Exceptions {
  PyObject* error = nullptr;
  PyObject* invalid_argument = nullptr;
  PyObject* format_error = nullptr;
  PyObject* io_error = nullptr;
  PyObject* numerical_error = nullptr;
};
Exceptions exceptions;

PyObject* new_exception(py::module_& m, const char* name, const char* doc, std::vector<PyObject*> bases) {
  py::tuple base_tuple(bases.size());
  for (std::size_t i = 0; i < bases.size(); ++i) base_tuple[i] = py::reinterpret_borrow<py::object>(bases[i]);
  const std::string qualified = std::string("contactnn.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, base_tuple.ptr(), nullptr);
  if (type == nullptr) throw py::error_already_set();
  m.add_object(name, py::handle(type));
  return type;
}

void raise(PyObject* type, const Error& e) {
  py::object instance = py::reinterpret_steal<py::object>(PyObject_CallFunction(type, "s", e.what()));
  if (!instance) return;  // the call's own exception stands
  instance.attr("exit_code") = e.exit_code();
  PyErr_SetObject(type, instance.ptr());
}

void translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const InvalidArgument& e) {
    raise(exceptions.invalid_argument, e);
  } catch (const FormatError& e) {
    raise(exceptions.format_error, e);
  } catch (const IoError& e) {
    raise(exceptions.io_error, e);
  } catch (const NumericalError& e) {
    raise(exceptions.numerical_error, e);
  } catch (const Error& e) {
    raise(exceptions.error, e);
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Arrays.

/// `object` as an array: itself when it is one (never copied), else np.asarray's reading of a list or tuple.
py::array as_array(const py::handle& object) {
  if (py::isinstance<py::array>(object)) return py::reinterpret_borrow<py::array>(object);
  return py::module_::import("numpy").attr("asarray")(object);
}

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_text(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

/// What a message names ("LocalSearch.run: raw"), in two parts joined only when a message is made: a call
/// that passes its checks builds no string.
struct What {
  const char* head;
  const char* tail = "";
  What(const char* h, const char* t = "") : head(h), tail(t) {}  // NOLINT: implicit by design
  What(const std::string& h) : head(h.c_str()) {}                // NOLINT
  [[nodiscard]] std::string text() const { return std::string(head) + tail; }
};

[[noreturn]] void refuse_type(const std::string& message) { throw py::type_error(message); }
[[noreturn]] void refuse_value(const std::string& message) { throw py::value_error(message); }

/// True for float32, false for float64; TypeError naming `what` otherwise.
bool is_float32(const py::array& a, const What& what) {
  if (a.dtype().is(py::dtype::of<double>())) return false;
  if (a.dtype().is(py::dtype::of<float>())) return true;
  refuse_type(what.text() + ": dtype " + dtype_text(a) +
              ", expected float64 or float32 (convert it with .astype)");
}

void require_c_contiguous(const py::array& a, const What& what) {
  if ((a.flags() & py::array::c_style) == 0)
    refuse_value(
        what.text() +
        ": not C-contiguous (a slice or a transpose; np.ascontiguousarray(...) makes a copy that is)");
}

/// A 2-D array of `columns` columns (any row count).
void require_rows(const py::array& a, py::ssize_t columns, const What& what) {
  if (a.ndim() != 2 || a.shape(1) != columns)
    refuse_value(what.text() + ": shape " + shape_text(a) + ", expected (n, " + std::to_string(columns) +
                 ")");
}

/// An output array of exactly dtype T, the given shape, C-contiguous and writable.
template <class T>
py::array_t<T> checked_output(const py::handle& object, std::initializer_list<py::ssize_t> shape,
                              const What& what) {
  if (!py::isinstance<py::array>(object)) refuse_type(what.text() + ": not a numpy array");
  auto a = py::reinterpret_borrow<py::array>(object);
  if (!a.dtype().is(py::dtype::of<T>()))
    refuse_type(what.text() + ": dtype " + dtype_text(a) + ", expected " +
                py::str(py::dtype::of<T>()).cast<std::string>());
  bool same = a.ndim() == static_cast<py::ssize_t>(shape.size());
  for (std::size_t d = 0; same && d < shape.size(); ++d)
    same = a.shape(static_cast<py::ssize_t>(d)) == shape.begin()[d];
  if (!same) {
    std::string expected = "(";
    for (std::size_t d = 0; d < shape.size(); ++d)
      expected += (d ? ", " : "") + std::to_string(shape.begin()[d]);
    refuse_value(what.text() + ": shape " + shape_text(a) + ", expected " + expected +
                 (shape.size() == 1 ? ",)" : ")"));
  }
  require_c_contiguous(a, what);
  if (!a.writeable()) refuse_value(what.text() + ": read-only");
  return py::reinterpret_borrow<py::array_t<T>>(a);
}

// ---------------------------------------------------------------------------------------------------------------
// Networks.

/// A network file's content (or a network made from weight arrays), in its own real type.
struct Network {
  std::variant<io::TrainedNetwork<float>, io::TrainedNetwork<double>> trained;
  /// lib/search's inference copy, made on first use by a LocalSearch (immutable, shared by every search).
  mutable std::shared_ptr<const search::NetworkModel> model;

  template <class F>
  decltype(auto) visit(F&& f) const {
    return std::visit([&](const auto& t) -> decltype(auto) { return f(t); }, trained);
  }
  [[nodiscard]] const geometry::TrainingDomain& domain() const {
    return visit([](const auto& t) -> const geometry::TrainingDomain& { return t.domain; });
  }
  [[nodiscard]] const search::NetworkModel& search_model() const {
    if (!model)
      model = visit(
          [](const auto& t) { return std::make_shared<const search::NetworkModel>(t.network, t.domain); });
    return *model;
  }
};

std::shared_ptr<Network> read_network(const std::string& path) {
  if (io::read_network_real_type(path) == "float32")
    return std::make_shared<Network>(Network{io::read_network<float>(path), {}});
  return std::make_shared<Network>(Network{io::read_network<double>(path), {}});
}

std::vector<double> vector_of(const py::handle& object, const std::string& what) {
  py::array a = as_array(object);
  if (a.ndim() != 1) refuse_value(what + ": shape " + shape_text(a) + ", expected one dimension");
  auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
  if (!d) refuse_type(what + ": dtype " + dtype_text(a) + ", expected numbers");
  return {d.data(), d.data() + d.size()};
}

/// A network from weight arrays: weights[l] of shape (n_{l+1}, n_l), thresholds[l] of n_{l+1} (Eq 13).
std::shared_ptr<Network> make_network(const py::list& weights, const py::list& thresholds, double u0,
                                      const py::handle& input_min, const py::handle& input_max,
                                      const py::handle& output_min, const py::handle& output_max,
                                      double target_low, double target_high, const std::string& surface,
                                      const py::object& feature_min, const py::object& feature_max,
                                      const std::string& input_features, const std::string& real_type) {
  if (weights.empty() || weights.size() != thresholds.size())
    refuse_value("network: " + std::to_string(weights.size()) + " weight arrays and " +
                 std::to_string(thresholds.size()) + " threshold arrays, expected as many, at least one");
  std::vector<int> sizes;
  std::vector<py::array_t<double, py::array::c_style | py::array::forcecast>> w, t;
  for (std::size_t l = 0; l < weights.size(); ++l) {
    const std::string at = "network: weights[" + std::to_string(l) + "]";
    py::array a = as_array(weights[l]);
    if (a.ndim() != 2) refuse_value(at + ": shape " + shape_text(a) + ", expected (n_out, n_in)");
    if (l == 0) sizes.push_back(static_cast<int>(a.shape(1)));
    if (a.shape(1) != sizes.back())
      refuse_value(at + ": shape " + shape_text(a) + ", expected " + std::to_string(sizes.back()) +
                   " columns (the units of the layer before)");
    sizes.push_back(static_cast<int>(a.shape(0)));
    w.push_back(py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a));
    py::array b = as_array(thresholds[l]);
    if (b.ndim() != 1 || b.shape(0) != a.shape(0))
      refuse_value("network: thresholds[" + std::to_string(l) + "]: shape " + shape_text(b) + ", expected (" +
                   std::to_string(a.shape(0)) + ",)");
    t.push_back(py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(b));
    if (!w.back() || !t.back())
      refuse_type("network: layer " + std::to_string(l) + ": arrays of numbers expected");
  }
  mlp::Scaling scaling;
  scaling.input_features = input_features_from_string(input_features);
  scaling.input_min = vector_of(input_min, "network: input_min");
  scaling.input_max = vector_of(input_max, "network: input_max");
  scaling.output_min = vector_of(output_min, "network: output_min");
  scaling.output_max = vector_of(output_max, "network: output_max");
  scaling.target_low = target_low;
  scaling.target_high = target_high;
  scaling.validate(sizes.front(), sizes.back());
  geometry::TrainingDomain domain;
  domain.surface = surface_from_string(surface);
  const std::size_t features = static_cast<std::size_t>(feature_count(domain.surface));
  domain.feature_min = feature_min.is_none() ? std::vector<double>(features, -1e300)
                                             : vector_of(feature_min, "network: feature_min");
  domain.feature_max = feature_max.is_none() ? std::vector<double>(features, 1e300)
                                             : vector_of(feature_max, "network: feature_max");
  auto fill = [&](auto& network) {
    for (std::size_t l = 0; l < w.size(); ++l) {
      const int layer = static_cast<int>(l);
      std::copy(w[l].data(), w[l].data() + w[l].size(), network.weights(layer));
      std::copy(t[l].data(), t[l].data() + t[l].size(), network.thresholds(layer));
    }
  };
  io::NetworkProvenance provenance;
  provenance.training_mode = "python";
  mlp::Network<double> network(sizes, u0, scaling);
  fill(network);
  if (real_type == "float64")
    return std::make_shared<Network>(
        Network{io::TrainedNetwork<double>{std::move(network), domain, provenance}, {}});
  if (real_type == "float32")
    return std::make_shared<Network>(
        Network{io::TrainedNetwork<float>{network.cast<float>(), domain, provenance}, {}});
  refuse_value("network: real_type '" + real_type + "', expected float64 or float32");
}

/// Per layer l of `net`, a float64 copy: W_l of shape (n_{l+1}, n_l) (`weights`), else theta_l of n_{l+1}
/// values.
template <class Net>
py::list layer_arrays(const Net& net, bool weights) {
  py::list out;
  for (int l = 0; l < net.layer_count(); ++l) {
    const auto rows = net.layer_sizes()[static_cast<std::size_t>(l) + 1];
    const auto cols = weights ? net.layer_sizes()[static_cast<std::size_t>(l)] : 1;
    py::array_t<double> a =
        weights ? py::array_t<double>({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)})
                : py::array_t<double>(rows);
    const auto* from = weights ? net.weights(l) : net.thresholds(l);
    std::copy(from, from + rows * cols, a.mutable_data());
    out.append(a);
  }
  return out;
}

py::array_t<double> network_evaluate(const Network& n, const py::handle& object) {
  py::array features = as_array(object);
  const int inputs = n.visit([](const auto& t) { return t.network.input_count(); });
  const int outputs = n.visit([](const auto& t) { return t.network.output_count(); });
  if (!features.dtype().is(py::dtype::of<double>()))
    refuse_type("Network.evaluate: features: dtype " + dtype_text(features) + ", expected float64");
  require_rows(features, inputs, "Network.evaluate: features");
  require_c_contiguous(features, "Network.evaluate: features");
  const auto rows = features.shape(0);
  py::array_t<double> out({rows, static_cast<py::ssize_t>(outputs)});
  const auto* in = static_cast<const double*>(features.data());
  double* o = out.mutable_data();
  {
    py::gil_scoped_release release;
    n.visit([&](const auto& t) {
      using Real = typename std::decay_t<decltype(t.network.parameters())>::value_type;
      mlp::ForwardPass<Real> pass(t.network);
      for (py::ssize_t r = 0; r < rows; ++r) mlp::predict(t.network, in + r * inputs, o + r * outputs, pass);
    });
  }
  return out;
}

// ---------------------------------------------------------------------------------------------------------------
// Local searches (LocalSearch on quad4 segments, FaceSearch on tri3, tri6, quad8).

template <class Search>
struct Searcher {
  Search search;
  std::shared_ptr<const void> network;  ///< the search's network, kept alive as long as the search
  std::uintptr_t last_input = 0;  ///< the address the last run read its queries from (the zero-copy test)
};

/// run(raw, out, threads) of either search: (param, gap, status) of the input's dtype (status uint8).
template <class Search>
py::tuple run_search(Searcher<Search>& s, const py::handle& raw_object, py::ssize_t columns,
                     const py::object& out, int threads, const char* name) {
  py::array raw = as_array(raw_object);
  const bool single = is_float32(raw, {name, ".run: raw"});
  require_rows(raw, columns, {name, ".run: raw"});
  require_c_contiguous(raw, {name, ".run: raw"});
  const py::ssize_t n = raw.shape(0);
  auto go = [&](auto zero) -> py::tuple {
    using Real = decltype(zero);
    py::array_t<Real> param, gap;
    py::array_t<std::uint8_t> status;
    if (out.is_none()) {
      param = py::array_t<Real>({n, py::ssize_t{2}});
      gap = py::array_t<Real>(n);
      status = py::array_t<std::uint8_t>(n);
    } else {
      if (!py::isinstance<py::sequence>(out)) refuse_type("out: a tuple (param, gap, status) expected");
      const auto t = py::reinterpret_borrow<py::sequence>(out);
      if (t.size() != 3)
        refuse_value(std::string(name) + ".run: out: " + std::to_string(t.size()) +
                     " arrays, expected 3 (param, gap, status)");
      param = checked_output<Real>(t[0], {n, 2}, {name, ".run: out[0] (param)"});
      gap = checked_output<Real>(t[1], {n}, {name, ".run: out[1] (gap)"});
      status = checked_output<std::uint8_t>(t[2], {n}, {name, ".run: out[2] (status)"});
    }
    const auto* in = static_cast<const Real*>(raw.data());
    s.last_input = reinterpret_cast<std::uintptr_t>(in);
    search::Results<Real> results{param.mutable_data(), gap.mutable_data(),
                                  reinterpret_cast<Status*>(status.mutable_data()), nullptr, nullptr};
    {
      py::gil_scoped_release release;
      s.search.template run<Real>(static_cast<std::size_t>(n), in, results, threads);
    }
    return py::make_tuple(param, gap, status);
  };
  return single ? go(0.0f) : go(0.0);
}

/// The fastest of `repeats` runs of the search itself on `raw` (seconds), timed in C++ around the library's
/// call alone: what scripts/bench-python compares the module's calls with.
template <class Search>
double time_search(const Searcher<Search>& s, const py::handle& raw_object, py::ssize_t columns,
                   const py::object& out, int repeats, int threads) {
  py::array raw = as_array(raw_object);
  const bool single = is_float32(raw, "_time_run: raw");
  require_rows(raw, columns, "_time_run: raw");
  require_c_contiguous(raw, "_time_run: raw");
  const auto n = static_cast<std::size_t>(raw.shape(0));
  auto go = [&](auto zero) {
    using Real = decltype(zero);
    std::vector<Real> param_buffer, gap_buffer;
    std::vector<Status> status_buffer;
    search::Results<Real> results;
    const auto rows = static_cast<py::ssize_t>(n);
    if (out.is_none()) {
      param_buffer.resize(2 * n);
      gap_buffer.resize(n);
      status_buffer.resize(n);
      results = {param_buffer.data(), gap_buffer.data(), status_buffer.data(), nullptr, nullptr};
    } else {  // the caller's arrays, as run(raw, out=...) writes them
      if (!py::isinstance<py::sequence>(out)) refuse_type("out: a tuple (param, gap, status) expected");
      const auto t = py::reinterpret_borrow<py::sequence>(out);
      if (t.size() != 3) refuse_value("_time_run: out: 3 arrays expected (param, gap, status)");
      results = {checked_output<Real>(t[0], {rows, 2}, "_time_run: out[0]").mutable_data(),
                 checked_output<Real>(t[1], {rows}, "_time_run: out[1]").mutable_data(),
                 reinterpret_cast<Status*>(
                     checked_output<std::uint8_t>(t[2], {rows}, "_time_run: out[2]").mutable_data()),
                 nullptr, nullptr};
    }
    const auto* in = static_cast<const Real*>(raw.data());
    double best = std::numeric_limits<double>::infinity();
    py::gil_scoped_release release;
    for (int r = 0; r < std::max(repeats, 1); ++r) {
      const auto start = std::chrono::steady_clock::now();
      s.search.template run<Real>(n, in, results, threads);
      best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
  };
  return single ? go(0.0f) : go(0.0);
}

// ---------------------------------------------------------------------------------------------------------------
// The contact search handle.

/// One update's answers, per slave point (contact_search.hpp).
struct Contacts {
  py::array_t<std::int32_t> status, face, location;
  py::array_t<double> param, point, gap, normal;
  explicit Contacts(py::ssize_t m)
      : status(m),
        face(m),
        location(m),
        param({m, py::ssize_t{2}}),
        point({m, py::ssize_t{3}}),
        gap(m),
        normal({m, py::ssize_t{3}}) {}
};

mesh::FaceType face_type_from(const py::handle& item) {
  if (py::isinstance<py::str>(item)) {
    const auto name = item.cast<std::string>();
    for (auto t :
         {mesh::FaceType::kQuad4, mesh::FaceType::kQuad8, mesh::FaceType::kTri3, mesh::FaceType::kTri6}) {
      if (mesh::to_string(t) == name) return t;
    }
    refuse_value("ContactSearch: face type '" + name + "', expected quad4, quad8, tri3 or tri6");
  }
  const long code = item.cast<long>();
  if (code < 0 || code > 3)
    refuse_value("ContactSearch: face type " + std::to_string(code) +
                 ", expected 0 to 3 (quad4, quad8, tri3, tri6)");
  return static_cast<mesh::FaceType>(code);
}

std::vector<long> ids_of(const py::handle& object, const std::string& what) {
  py::array a = as_array(object);
  if (a.ndim() == 2) a = a.attr("reshape")(-1);
  if (a.ndim() != 1) refuse_value(what + ": shape " + shape_text(a) + ", expected one dimension");
  if (a.size() > 0 && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    refuse_type(what + ": dtype " + dtype_text(a) + ", expected integers");
  auto l = py::array_t<long, py::array::c_style | py::array::forcecast>::ensure(a);
  return {l.data(), l.data() + l.size()};
}

struct Handle {
  std::unique_ptr<contact::ContactSearch> search;
  long nodes = 0, slaves = 0;
  bool free = false;
  std::uintptr_t last_input = 0;
  /// An update is running with the GIL released: another thread may neither update nor close the handle (read
  /// and written with the GIL held only).
  bool busy = false;

  contact::ContactSearch& get() {
    if (!search) refuse_value("ContactSearch: the handle is closed");
    if (busy) throw std::runtime_error("ContactSearch: an update is running in another thread");
    return *search;
  }
  void close() {
    if (busy) throw std::runtime_error("ContactSearch: an update is running in another thread");
    search.reset();
  }
};

std::unique_ptr<Handle> make_handle(const py::iterable& face_types, const py::handle& connectivity,
                                    std::optional<long> node_count, const py::object& ids, long base,
                                    const py::object& slave_nodes, long free_points, double capture_distance,
                                    const std::string& quad4, int threads, bool tracking,
                                    const std::string& method, const std::string& network) {
  std::vector<mesh::FaceType> types;
  if (py::isinstance<py::array>(face_types)) {
    for (const auto& v : ids_of(face_types, "ContactSearch: face_types"))
      types.push_back(face_type_from(py::int_(v)));
  } else {
    for (const auto& item : face_types) types.push_back(face_type_from(item));
  }
  const std::vector<long> conn = ids_of(connectivity, "ContactSearch: connectivity");
  std::vector<long> id_list;
  if (!ids.is_none()) id_list = ids_of(ids, "ContactSearch: ids");
  contact::NodeNumbering numbering;
  if (node_count) {
    numbering.count = *node_count;
  } else if (!ids.is_none()) {
    numbering.count = static_cast<long>(id_list.size());
  } else {
    refuse_value("ContactSearch: give node_count (the rows of the coordinate array) or ids");
  }
  numbering.base = base;
  numbering.ids = id_list;
  std::vector<long> slaves;
  if (!slave_nodes.is_none()) slaves = ids_of(slave_nodes, "ContactSearch: slave_nodes");
  contact::SlavePoints points{slaves, free_points};
  contact::ContactSearchOptions options;
  options.capture_distance = capture_distance;
  options.quad4 = surface_from_string(quad4);
  options.threads = threads;
  options.tracking = tracking;
  options.method = method;
  if (!network.empty()) options.network = io::read_network_model(network);
  auto h = std::make_unique<Handle>();
  h->search = std::make_unique<contact::ContactSearch>(types, conn, numbering, points, options);
  h->nodes = h->search->node_count();
  h->slaves = h->search->slave_count();
  h->free = h->search->free_points();
  return h;
}

/// A (rows, 3) array of coordinates: float64 read in place, float32 converted (the handle computes in
/// double).
py::array_t<double> coordinate_rows(const py::handle& object, long rows, const What& what) {
  py::array a = as_array(object);
  const bool single = is_float32(a, what);
  if (a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != 3)
    refuse_value(what.text() + ": shape " + shape_text(a) + ", expected (" + std::to_string(rows) + ", 3)");
  require_c_contiguous(a, what);
  if (single) return py::array_t<double>(a.attr("astype")("float64"));
  return py::reinterpret_borrow<py::array_t<double>>(a);
}

Contacts& update(Handle& h, const py::handle& coordinates, const py::object& free_points, Contacts* out_given,
                 std::optional<Contacts>& out_made) {
  contact::ContactSearch& search = h.get();
  const py::array_t<double> x = coordinate_rows(coordinates, h.nodes, "ContactSearch.update: coordinates");
  py::array_t<double> f;
  if (h.free) {
    if (free_points.is_none())
      refuse_value("ContactSearch.update: free_points: the handle was made for free points");
    f = coordinate_rows(free_points, h.slaves, "ContactSearch.update: free_points");
  } else if (!free_points.is_none()) {
    refuse_value("ContactSearch.update: free_points given to a handle of slave nodes");
  }
  Contacts* out = out_given;
  if (out == nullptr) {
    out_made.emplace(h.slaves);
    out = &*out_made;
  } else {
    const py::ssize_t m = h.slaves;
    const std::string at = "ContactSearch.update: out.";
    checked_output<std::int32_t>(out->status, {m}, at + "status");
    checked_output<std::int32_t>(out->face, {m}, at + "face");
    checked_output<std::int32_t>(out->location, {m}, at + "location");
    checked_output<double>(out->param, {m, 2}, at + "param");
    checked_output<double>(out->point, {m, 3}, at + "point");
    checked_output<double>(out->gap, {m}, at + "gap");
    checked_output<double>(out->normal, {m, 3}, at + "normal");
  }
  h.last_input = reinterpret_cast<std::uintptr_t>(x.data());
  const auto m = static_cast<std::size_t>(h.slaves);
  contact::ContactResults r{{out->status.mutable_data(), m},    {out->face.mutable_data(), m},
                            {out->location.mutable_data(), m},  {out->param.mutable_data(), 2 * m},
                            {out->point.mutable_data(), 3 * m}, {out->gap.mutable_data(), m},
                            {out->normal.mutable_data(), 3 * m}};
  const std::span<const double> xs(x.data(), static_cast<std::size_t>(x.size()));
  const std::span<const double> fs =
      h.free ? std::span<const double>(f.data(), static_cast<std::size_t>(f.size()))
             : std::span<const double>();
  struct Busy {
    bool& flag;
    explicit Busy(bool& f) : flag(f) { flag = true; }
    ~Busy() { flag = false; }  // after the GIL is taken back (declared before the release)
  } busy(h.busy);
  {
    py::gil_scoped_release release;
    search.update(xs, fs, r);
  }
  return *out;
}

// ---------------------------------------------------------------------------------------------------------------
// Decks, scenes and CalculiX results.

struct Results {
  io::FrdResults frd;
};

/// A contact pair of a deck in the handle's terms (as tests/contact/test_contact_search.cpp makes it): every
/// node of the pair, master surface and slave nodes, in increasing deck id; the master faces in increasing
/// (element id, face number), SPEC 9's tie order, so that the handle's answers are the deck search's; the
/// connectivity in deck ids.
struct Scene {
  mesh::ContactModel model;  ///< its own copy: coordinates() moves its nodes to an increment
  int pair = 0;
  std::string slave_name, master_name, where;
  std::vector<long> node_ids;
  std::vector<int> mesh_index;  ///< SolidMesh index of each node
  std::vector<std::uint8_t> face_types;
  std::vector<long> connectivity;
  std::vector<long> face_elements;
  std::vector<int> face_numbers;
  std::vector<std::uint8_t> face_segments;  ///< 1 for a segment (SPEC 7), 0 for an extra face (SPEC 9)
  std::vector<long> slave_ids;
  const io::FrdResults* checked =
      nullptr;  ///< the results whose node block was last checked against the deck
};

std::unique_ptr<Scene> make_scene(const mesh::ContactModel& model, int pair) {
  const contact::Scene scene = contact::make_scene(model, pair);
  if (scene.cyclic_sectors > 0)
    refuse_value(
        "scene: pair " + std::to_string(pair) + " (" + scene.where +
        ") is a cyclic symmetry model's: its master surface repeats node ids in each sector, which the "
        "contact search handle does not take");
  auto s = std::make_unique<Scene>();
  s->model = model;
  s->pair = pair;
  s->slave_name = scene.slave_name;
  s->master_name = scene.master_name;
  s->where = scene.where;
  std::vector<std::pair<long, int>> nodes;
  for (std::size_t i = 0; i < scene.master.node_ids.size(); ++i)
    nodes.emplace_back(scene.master.node_ids[i], scene.master.mesh_nodes[i]);
  for (std::size_t i = 0; i < scene.slave_ids.size(); ++i)
    nodes.emplace_back(scene.slave_ids[i], scene.slaves.nodes[i]);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  for (const auto& [id, index] : nodes) {
    s->node_ids.push_back(id);
    s->mesh_index.push_back(index);
  }
  for (int f : contact::master_faces_in_deck_order(scene)) {
    const mesh::FaceNodes face = scene.master.face_nodes(f);
    s->face_types.push_back(static_cast<std::uint8_t>(face.type));
    for (int k : face) s->connectivity.push_back(scene.master.node_ids[static_cast<std::size_t>(k)]);
    s->face_elements.push_back(scene.master.face_element_id(f));
    s->face_numbers.push_back(scene.master.face_of(f).face);
    s->face_segments.push_back(static_cast<std::size_t>(f) < scene.master.segments.size() ? 1 : 0);
  }
  s->slave_ids = scene.slave_ids;
  return s;
}

py::array_t<double> scene_coordinates(Scene& s, const Results* results, int increment, bool trust_nodes) {
  if (results != nullptr) {
    if (!trust_nodes && s.checked != &results->frd) {
      io::check_node_block(s.model, results->frd);
      s.checked = &results->frd;
    }
    io::move_to_increment(s.model.mesh, results->frd, io::increment_index(results->frd, increment));
  }
  py::array_t<double> x({static_cast<py::ssize_t>(s.node_ids.size()), py::ssize_t{3}});
  double* o = x.mutable_data();
  for (std::size_t i = 0; i < s.mesh_index.size(); ++i) {
    const auto& p = results != nullptr ? s.model.mesh.position(s.mesh_index[i])
                                       : s.model.mesh.deck_position(s.mesh_index[i]);
    for (int k = 0; k < 3; ++k) o[3 * i + static_cast<std::size_t>(k)] = p[k];
  }
  return x;
}

template <class T>
py::array_t<T> array_of(const std::vector<T>& v) {
  py::array_t<T> a(static_cast<py::ssize_t>(v.size()));
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

}  // namespace
}  // namespace contactnn::python

PYBIND11_MODULE(_contactnn, m) {
  using namespace contactnn;
  using namespace contactnn::python;
  m.doc() = "contactnn's searches, decks, CalculiX results and networks from numpy (docs/python.md)";

  exceptions.error = new_exception(m, "Error", "A contactnn error; exit_code is the tools' exit code for it.",
                                   {PyExc_RuntimeError});
  exceptions.invalid_argument = new_exception(m, "InvalidArgument", "A value outside its documented range.",
                                              {exceptions.error, PyExc_ValueError});
  exceptions.format_error = new_exception(m, "FormatError", "A file's content is not what was expected.",
                                          {exceptions.error, PyExc_ValueError});
  exceptions.io_error = new_exception(m, "IoError", "A file cannot be opened, read or written.",
                                      {exceptions.error, PyExc_OSError});
  exceptions.numerical_error =
      new_exception(m, "NumericalError", "A non-finite value where a finite one is required.",
                    {exceptions.error, PyExc_ArithmeticError});
  py::register_exception_translator(&translate);

  py::list statuses, locations, face_types;
  for (int s = 0; s < kStatusCount; ++s) statuses.append(std::string(to_string(static_cast<Status>(s))));
  for (int l = 0; l < 3; ++l) locations.append(std::string(to_string(static_cast<Location>(l))));
  for (int t = 0; t < 4; ++t) face_types.append(std::string(mesh::to_string(static_cast<mesh::FaceType>(t))));
  m.attr("STATUS_NAMES") = py::tuple(statuses);
  m.attr("LOCATION_NAMES") = py::tuple(locations);
  m.attr("FACE_TYPES") = py::tuple(face_types);

  // Networks.
  py::class_<Network, std::shared_ptr<Network>>(m, "Network",
                                                "A network file's network: weights, scaling, domain.")
      .def_property_readonly("surface",
                             [](const Network& n) { return std::string(to_string(n.domain().surface)); })
      .def_property_readonly(
          "real_type",
          [](const Network& n) {
            return n.visit([](const auto& t) {
              return std::string(std::is_same_v<std::decay_t<decltype(t)>, io::TrainedNetwork<float>>
                                     ? "float32"
                                     : "float64");
            });
          })
      .def_property_readonly(
          "layer_sizes",
          [](const Network& n) { return n.visit([](const auto& t) { return t.network.layer_sizes(); }); })
      .def_property_readonly(
          "u0", [](const Network& n) { return n.visit([](const auto& t) { return t.network.u0(); }); })
      .def_property_readonly(
          "weights",
          [](const Network& n) {
            return n.visit([](const auto& t) { return layer_arrays(t.network, true); });
          },
          "W_l, float64 arrays of shape (n_{l+1}, n_l) (Eq 13: row j holds unit j's incoming weights)")
      .def_property_readonly(
          "thresholds",
          [](const Network& n) {
            return n.visit([](const auto& t) { return layer_arrays(t.network, false); });
          },
          "theta_l, float64 arrays of n_{l+1} values (U_j = sum_i W_ji I_i - theta_j)")
      .def_property_readonly("scaling",
                             [](const Network& n) {
                               const mlp::Scaling& s = n.visit(
                                   [](const auto& t) -> const mlp::Scaling& { return t.network.scaling(); });
                               py::dict d;
                               d["input_features"] = std::string(to_string(s.input_features));
                               d["input_min"] = array_of(s.input_min);
                               d["input_max"] = array_of(s.input_max);
                               d["output_min"] = array_of(s.output_min);
                               d["output_max"] = array_of(s.output_max);
                               d["target_low"] = s.target_low;
                               d["target_high"] = s.target_high;
                               return d;
                             })
      .def_property_readonly("feature_min", [](const Network& n) { return array_of(n.domain().feature_min); })
      .def_property_readonly("feature_max", [](const Network& n) { return array_of(n.domain().feature_max); })
      .def("evaluate", &network_evaluate, py::arg("features"),
           "Raw outputs (n, n_out) of the network on features (n, n_in) float64: scaling, Eqs 12-13, inverse "
           "scaling")
      .def(
          "write",
          [](const Network& n, const std::string& path) {
            n.visit([&](const auto& t) { io::write_network(path, t.network, t.domain, t.provenance); });
          },
          py::arg("path"), "Writes the network file (atomically).");
  m.def("read_network", &read_network, py::arg("path"), "Reads a network file of train-net (docs/files.md).");
  m.def("make_network", &make_network, py::arg("weights"), py::arg("thresholds"), py::kw_only(),
        py::arg("u0") = 1.0, py::arg("input_min"), py::arg("input_max"), py::arg("output_min"),
        py::arg("output_max"), py::arg("target_low") = 0.1, py::arg("target_high") = 0.9,
        py::arg("surface") = "bilinear", py::arg("feature_min") = py::none(),
        py::arg("feature_max") = py::none(), py::arg("input_features") = "paper",
        py::arg("real_type") = "float64",
        "A network from weight arrays: weights[l] (n_{l+1}, n_l), thresholds[l] (n_{l+1}), Eqs 12-13's U0 "
        "and the "
        "scaling of mlp::Scaling; its training domain is feature_min/feature_max (default: unbounded).");

  // Local searches.
  using LocalSearcher = Searcher<search::LocalSearch>;
  py::class_<LocalSearcher>(m, "LocalSearch", "lib/search's batched local search on quad4 segments.")
      .def(py::init(
               [](const std::string& surface, const std::string& method, std::shared_ptr<Network> network) {
                 const SurfaceKind kind = surface_from_string(surface);
                 const search::NetworkModel* model = network ? &network->search_model() : nullptr;
                 return LocalSearcher{search::LocalSearch(kind, search::Method::parse(method), {}, model),
                                      network};
               }),
           py::arg("surface"), py::arg("method"), py::arg("network") = nullptr)
      .def(
          "run",
          [](LocalSearcher& s, const py::handle& raw, const py::object& out, int threads) {
            return run_search(s, raw, search::LocalSearch::raw_columns(s.search.surface()), out, threads,
                              "LocalSearch");
          },
          py::arg("raw"), py::kw_only(), py::arg("out") = py::none(), py::arg("threads") = 0,
          "(params (n, 2), gaps (n,), statuses (n,) uint8) for raw rows (n, 15) bilinear or (n, 27) Gregory "
          "(SPEC 6)")
      .def_property_readonly(
          "surface", [](const LocalSearcher& s) { return std::string(to_string(s.search.surface())); })
      .def_property_readonly("method", [](const LocalSearcher& s) { return s.search.method().name(); })
      .def_property_readonly(
          "columns",
          [](const LocalSearcher& s) { return search::LocalSearch::raw_columns(s.search.surface()); })
      .def(
          "_time_run",
          [](const LocalSearcher& s, const py::handle& raw, const py::object& out, int repeats, int threads) {
            return time_search(s, raw, search::LocalSearch::raw_columns(s.search.surface()), out, repeats,
                               threads);
          },
          py::arg("raw"), py::kw_only(), py::arg("out") = py::none(), py::arg("repeats") = 5,
          py::arg("threads") = 0,
          "Benchmarks only: the fastest of `repeats` runs timed in C++ around the library's call (seconds)")
      .def_property_readonly(
          "last_input_address", [](const LocalSearcher& s) { return s.last_input; },
          "Address of the raw rows the last run read (compare with raw.ctypes.data: no copy)");
  py::class_<search::FaceNetwork, std::shared_ptr<search::FaceNetwork>>(
      m, "FaceNetwork", "A face network file's network (tri6 or quad8), for FaceSearch's network methods.")
      .def_property_readonly(
          "face", [](const search::FaceNetwork& n) { return std::string(search::to_string(n.face())); });
  m.def(
      "read_face_network",
      [](const std::string& path) {
        return std::shared_ptr<search::FaceNetwork>(io::load_face_network(path));
      },
      py::arg("path"), "Reads a face network file (scene-study --face, data/weights/tri6-48-48.h5).");
  using FaceSearcher = Searcher<search::FaceSearch>;
  py::class_<FaceSearcher>(m, "FaceSearch",
                           "lib/search's batched local search on tri3, tri6 and quad8 faces.")
      .def(py::init([](const std::string& face, const std::string& method,
                       std::shared_ptr<const search::FaceNetwork> network) {
             return FaceSearcher{search::FaceSearch(search::face_kind_from_string(face),
                                                    search::Method::parse(method), {}, network.get()),
                                 network};
           }),
           py::arg("face"), py::arg("method"), py::arg("network") = nullptr)
      .def(
          "run",
          [](FaceSearcher& s, const py::handle& raw, const py::object& out, int threads) {
            return run_search(s, raw, search::face_raw_columns(s.search.face()), out, threads, "FaceSearch");
          },
          py::arg("raw"), py::kw_only(), py::arg("out") = py::none(), py::arg("threads") = 0,
          "(params (n, 2), gaps (n,), statuses (n,) uint8) for raw rows (n, 12) tri3, (n, 21) tri6, (n, 27) "
          "quad8")
      .def_property_readonly(
          "face", [](const FaceSearcher& s) { return std::string(search::to_string(s.search.face())); })
      .def_property_readonly("method", [](const FaceSearcher& s) { return s.search.method().name(); })
      .def_property_readonly("columns",
                             [](const FaceSearcher& s) { return search::face_raw_columns(s.search.face()); })
      .def(
          "_time_run",
          [](const FaceSearcher& s, const py::handle& raw, const py::object& out, int repeats, int threads) {
            return time_search(s, raw, search::face_raw_columns(s.search.face()), out, repeats, threads);
          },
          py::arg("raw"), py::kw_only(), py::arg("out") = py::none(), py::arg("repeats") = 5,
          py::arg("threads") = 0)
      .def_property_readonly("last_input_address", [](const FaceSearcher& s) { return s.last_input; });

  // The contact search handle.
  py::class_<Contacts>(m, "Contacts",
                       "One update's answers per slave point (int32 status, face, location; "
                       "float64 param (m, 2), point (m, 3), gap (m,), normal (m, 3)).")
      .def(py::init<py::ssize_t>(), py::arg("m"))
      .def_readonly("status", &Contacts::status)
      .def_readonly("face", &Contacts::face)
      .def_readonly("location", &Contacts::location)
      .def_readonly("param", &Contacts::param)
      .def_readonly("point", &Contacts::point)
      .def_readonly("gap", &Contacts::gap)
      .def_readonly("normal", &Contacts::normal);
  py::class_<Handle>(m, "ContactSearch",
                     "contact::ContactSearch: the surface search of SPEC 9 with tracking.")
      .def(py::init(&make_handle), py::arg("face_types"), py::arg("connectivity"),
           py::arg("node_count") = std::nullopt, py::kw_only(), py::arg("ids") = py::none(),
           py::arg("base") = 0, py::arg("slave_nodes") = py::none(), py::arg("free_points") = 0,
           py::arg("capture_distance") = 0.0, py::arg("quad4") = "bilinear", py::arg("threads") = 0,
           py::arg("tracking") = true, py::arg("method") = "", py::arg("network") = "")
      .def(
          "update",
          [](Handle& h, const py::handle& coordinates, const py::object& free_points,
             Contacts* out) -> py::object {
            std::optional<Contacts> made;
            Contacts& r = update(h, coordinates, free_points, out, made);
            if (out != nullptr) return py::cast(out, py::return_value_policy::reference);
            return py::cast(std::move(r));
          },
          py::arg("coordinates"), py::arg("free_points") = py::none(), py::kw_only(),
          py::arg("out") = nullptr,
          "One increment: coordinates (node_count, 3) float64 (float32 is converted); returns Contacts (or "
          "fills out)")
      .def("close", [](Handle& h) { h.close(); })
      .def(
          "__enter__", [](Handle& h) -> Handle& { return h; }, py::return_value_policy::reference)
      .def("__exit__", [](Handle& h, const py::args&) { h.close(); })
      .def_property_readonly("closed", [](const Handle& h) { return !h.search; })
      .def_property_readonly("node_count", [](const Handle& h) { return h.nodes; })
      .def_property_readonly("slave_count", [](const Handle& h) { return h.slaves; })
      .def_property_readonly("face_count", [](Handle& h) { return h.get().face_count(); })
      .def_property_readonly("counts",
                             [](Handle& h) {
                               const contact::TrackingCounts& c = h.get().counts();
                               py::dict d;
                               d["fresh"] = c.fresh;
                               d["tracked"] = c.tracked;
                               d["warm"] = c.warm;
                               return d;
                             })
      .def_property_readonly("last_input_address", [](const Handle& h) { return h.last_input; });

  // Decks, scenes, results.
  py::class_<Results>(m, "Results", "A CalculiX .frd: its increments (SPEC 10).")
      .def_property_readonly("increment_count", [](const Results& r) { return r.frd.increments.size(); })
      .def_property_readonly("times",
                             [](const Results& r) {
                               std::vector<double> t;
                               for (const auto& i : r.frd.increments) t.push_back(i.time);
                               return array_of(t);
                             })
      .def_property_readonly("steps",
                             [](const Results& r) {
                               std::vector<int> s;
                               for (const auto& i : r.frd.increments) s.push_back(i.step);
                               return array_of(s);
                             })
      .def(
          "calculix_contact",
          [](const Results& r, int increment) {
            const io::FrdIncrement& inc = r.frd.increments[io::increment_index(r.frd, increment)];
            std::vector<long> nodes;
            std::vector<double> copen;
            for (const auto& c : inc.contact) {
              nodes.push_back(c.node);
              copen.push_back(c.copen);
            }
            return py::make_tuple(array_of(nodes), array_of(copen));
          },
          py::arg("increment"), "CalculiX's CONTACT block of increment N (from 1): (node ids, COPEN)");
  m.def(
      "read_results", [](const std::string& path) { return Results{io::read_frd(path)}; }, py::arg("path"),
      "Reads a CalculiX ASCII result file (.frd).");
  py::class_<mesh::ContactModel>(m, "Deck", "An Abaqus/CalculiX deck's mesh, surfaces and contact pairs.")
      .def_property_readonly("pair_count", [](const mesh::ContactModel& d) { return d.pairs.size(); })
      .def_property_readonly("pairs",
                             [](const mesh::ContactModel& d) {
                               py::list out;
                               for (const auto& p : d.pairs)
                                 out.append(py::make_tuple(p.slave_name, p.master_name));
                               return out;
                             })
      .def("scene", &make_scene, py::arg("pair") = 0, "The contact pair's scene (SPEC 7's K, from 0).");
  m.def(
      "read_deck", [](const std::string& path) { return io::read_inp_deck(path); }, py::arg("path"),
      "Reads a deck (.inp) as gen-configs --scene does.");
  py::class_<Scene>(m, "Scene", "A contact pair in the contact search handle's terms.")
      .def_readonly("pair", &Scene::pair)
      .def_readonly("slave_name", &Scene::slave_name)
      .def_readonly("master_name", &Scene::master_name)
      .def_readonly("where", &Scene::where)
      .def_property_readonly(
          "node_ids", [](const Scene& s) { return array_of(s.node_ids); },
          "Deck ids of the coordinate array's rows (master and slave nodes, increasing)")
      .def_property_readonly(
          "face_types", [](const Scene& s) { return array_of(s.face_types); },
          "Each master face's type, an index into FACE_TYPES")
      .def_property_readonly(
          "connectivity", [](const Scene& s) { return array_of(s.connectivity); },
          "The faces' node ids (deck ids), concatenated, in SPEC 9's order")
      .def_property_readonly("face_elements", [](const Scene& s) { return array_of(s.face_elements); })
      .def_property_readonly("face_numbers", [](const Scene& s) { return array_of(s.face_numbers); })
      .def_property_readonly(
          "face_segments", [](const Scene& s) { return array_of(s.face_segments); },
          "1 for a segment (SPEC 7), 0 for another face (SPEC 9): a deck's C3D6 quadrilateral "
          "is a quad4 that stays a bilinear facet under --surface gregory, unlike the handle's")
      .def_property_readonly("slave_ids", [](const Scene& s) { return array_of(s.slave_ids); })
      .def(
          "coordinates",
          [](Scene& s, const Results* results, int increment, bool trust) {
            return scene_coordinates(s, results, increment, trust);
          },
          py::arg("results") = nullptr, py::arg("increment") = -1, py::kw_only(),
          py::arg("trust_results_nodes") = false,
          "(node_count, 3) float64: the deck's positions, or those of increment N (from 1; -1 the last) of "
          "results");
}
