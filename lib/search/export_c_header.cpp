#include "search/export_c_header.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.hpp"
#include "search/embedded_sources.hpp"

namespace contactnn::search {

namespace {

// Lanes per block of the batched entry point, and units of a layer computed together (independent
// multiply-add chains of kBlockLanes lanes each, so that a layer is bound by throughput rather than by the
// latency of one chain): the library's 32 and 8 (network_block.hpp). Measured with bench_search's c-header
// rows (batched, 1 thread, AMD EPYC with AVX-512): 16 lanes and 4 units took 1.47x (bilinear-8) and 1.75x
// (gregory-48) the library's time, 32 and 8 take 1.12x and 1.17x; compiled for AVX2 only (-mno-avx512f),
// 32 lanes are faster too (gregory-48 811 -> 562 us per 4096 queries), the frame's spills notwithstanding.
constexpr int kBlockLanes = 32;
constexpr int kUnitsTogether = 8;

// Text that reads back to the same value: 9 significant digits for float, 17 for double; the infinities of
// an open bound as HUGE_VAL (a constant expression in C99).
template <class Real>
std::string literal(Real v) {
  if (std::isinf(v)) return v > 0 ? "HUGE_VAL" : "(-HUGE_VAL)";
  char buf[40];
  if constexpr (std::is_same_v<Real, float>) {
    std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  } else {
    std::snprintf(buf, sizeof buf, "%.17g", v);
  }
  std::string s = buf;
  if (s.find_first_of(".eE") == std::string::npos) s += ".";  // "1" is an int, "1." a double
  if constexpr (std::is_same_v<Real, float>) s += "f";
  return s;
}

bool is_c_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (char c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  }
  return true;
}

// The value of `#define NAME value` in an embedded source: the generated header checks it, so that the copy
// in force in a translation unit (the first included) is the one the header was generated with.
std::string macro_value(std::string_view text, const std::string& name) {
  const std::string key = "#define " + name + " ";
  const auto at = text.find(key);
  CONTACTNN_REQUIRE(at != std::string_view::npos, "the embedded C source does not define " << name);
  const auto start = at + key.size();
  return std::string(text.substr(start, text.find('\n', start) - start));
}

template <class Real>
void table(std::ostringstream& o, const std::string& type, const std::string& name, const Real* v,
           std::size_t n, std::size_t per_line) {
  o << "static const " << type << " " << name << "[" << n << "] = {";
  for (std::size_t i = 0; i < n; ++i) {
    CONTACTNN_REQUIRE(std::isfinite(v[i]),
                      "the C header's table " << name << "[" << i << "] is not finite: " << v[i]);
    o << (i == 0 ? "" : ",") << (i % per_line == 0 ? "\n  " : " ") << literal(v[i]);
  }
  o << "};\n";
}

// The forward pass's opening: its comment, signature and the activation arrays a<l>.
void forward_opening(std::ostringstream& o, const NetworkModel& m, const std::string& p, bool one,
                     const std::string& net, const std::string& block) {
  const auto& sizes = m.layer_sizes();
  if (one) {
    o << "/* The network on one query's canonical features f[k] (n = 1 of " << p
      << "_forward, the same bits):\n"
      << " * canonical local coordinates est[c]. Each layer runs across its units. */\n"
      << "CNN_CF_INLINE void " << p
      << "_forward_one(const double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT est) {\n"
      << "  const int n = 1;\n";
  } else {
    o << "/* The network on n <= " << block
      << " lanes of canonical features f[k n + l] (cnn_canonicalise_block's\n"
      << " * layout): canonical local coordinates est[c n + l]. lib/search's forward pass "
         "(network_block.hpp) in the\n"
      << " * same operations and order: input map, input scaling clamped to +-1e6, each layer's sums (Eq 13) "
         "from\n"
      << " * -theta in input order, the sigmoid of Eq 12, output scaling. */\n"
      << "CNN_CF_INLINE void " << p
      << "_forward(int n, const double* CNN_CF_RESTRICT f, double* CNN_CF_RESTRICT est) {\n";
  }
  for (std::size_t l = 0; l < sizes.size(); ++l)
    o << "  " << net << " a" << l << "[" << sizes[l] << " * " << block << "];\n";
  o << "  const double* in = f;\n  int i, l;\n";
}

// The affine input features g (core/input_features), computed from f; the scaling then reads g.
void affine_features(std::ostringstream& o, const NetworkModel& m, const std::string& block) {
  const int n_features = m.layer_sizes()[0];
  const bool gregory = m.surface() == SurfaceKind::kGregory;
  o << "  double g[" << n_features << " * " << block << "];\n"
    << "  /* The affine input features (core/input_features: x = alpha + beta xd, y = beta yd; heights / "
       "sqrt(yd)). */\n"
    << "  CNN_CF_IVDEP\n"
    << "  for (l = 0; l < n; ++l) {\n"
    << "    const double xd = f[3 * n + l], y = f[4 * n + l];\n"
    << "    const double yd = y < 1e-300 ? 1e-300 : y;\n"
    << "    const double rho = sqrt(xd * xd + yd * yd);\n"
    << "    const double height = 1.0 / sqrt(yd);\n"
    << "    const double beta_c = f[1 * n + l] / yd, beta_s = f[6 * n + l] / yd;\n"
    << "    g[0 * n + l] = f[0 * n + l] - xd * beta_c;\n"
    << "    g[1 * n + l] = beta_c;\n"
    << "    g[2 * n + l] = f[2 * n + l] * height;\n"
    << "    g[3 * n + l] = rho;\n"
    << "    g[4 * n + l] = xd / rho;\n"
    << "    g[5 * n + l] = f[5 * n + l] - xd * beta_s;\n"
    << "    g[6 * n + l] = beta_s;\n"
    << "    g[7 * n + l] = f[7 * n + l] * height;\n"
    << "  }\n";
  if (gregory) {
    o << "  CNN_CF_IVDEP\n"
      << "  for (l = 0; l < n; ++l) {\n"
      << "    const double xd = f[3 * n + l], y = f[4 * n + l];\n"
      << "    const double yd = y < 1e-300 ? 1e-300 : y;\n"
      << "    const double rho = sqrt(xd * xd + yd * yd);\n"
      << "    int k;\n"
      << "    CNN_CF_UNROLL\n"
      << "    for (k = 0; k < 4; ++k) {\n"
      << "      const double pk = f[(8 + 2 * k) * n + l], qk = f[(9 + 2 * k) * n + l];\n"
      << "      g[(8 + 2 * k) * n + l] = pk;\n"
      << "      g[(9 + 2 * k) * n + l] = (pk * xd + qk * yd) / rho;\n"
      << "    }\n"
      << "  }\n";
  }
  o << "  in = g;\n";
}

// One layer of the one-query pass: across the units, with the transposed weights.
void layer_one(std::ostringstream& o, const std::string& net, const std::string& sigmoid,
               const std::string& p, int n_in, int n_out, const std::string& w, const std::string& theta,
               const std::string& x, const std::string& y) {
  o << "    " << net << " s[" << n_out << "];\n"
    << "    for (j = 0; j < " << n_out << "; ++j) s[j] = -" << theta << "[j];\n"
    << "    for (i = 0; i < " << n_in << "; ++i) {\n"
    << "      const " << net << " x = " << x << "[i];\n"
    << "      const " << net << "* CNN_CF_RESTRICT w = " << w << "t + i * " << n_out << ";\n"
    << "      CNN_CF_IVDEP\n"
    << "      for (j = 0; j < " << n_out << "; ++j) s[j] += w[j] * x;\n"
    << "    }\n"
    << "    CNN_CF_IVDEP\n"
    << "    for (j = 0; j < " << n_out << "; ++j) " << y << "[j] = " << sigmoid << "(s[j], " << p
    << "_gain);\n"
    << "  }\n";
}

// One layer of the block pass: groups of kUnitsTogether units, then single units; each unit's sum is the
// same chain either way. The bounds are constants (a loop that starts where another ended trips GCC's
// -Waggressive-loop-optimizations).
void layer_block(std::ostringstream& o, const std::string& net, const std::string& sigmoid,
                 const std::string& p, const std::string& block, int n_in, int n_out, const std::string& w,
                 const std::string& theta, const std::string& x, const std::string& y) {
  const int grouped = n_out - n_out % kUnitsTogether;
  for (const int units : {kUnitsTogether, 1}) {
    const int first = units == 1 ? grouped : 0, end = units == 1 ? n_out : grouped;
    if (first == end) continue;
    o << "    for (j = " << first << "; j < " << end << "; j += " << units << ") {\n"
      << "      " << net;
    for (int u = 0; u < units; ++u) o << (u ? ", " : " ") << "s" << u << "[" << block << "]";
    o << ";\n"
      << "      CNN_CF_IVDEP\n"
      << "      for (l = 0; l < n; ++l) {\n";
    for (int u = 0; u < units; ++u) o << "        s" << u << "[l] = -" << theta << "[j + " << u << "];\n";
    o << "      }\n"
      << "      for (i = 0; i < " << n_in << "; ++i) {\n"
      << "        const " << net << "* CNN_CF_RESTRICT x = " << x << " + i * n;\n";
    for (int u = 0; u < units; ++u) {
      o << "        const " << net << " w" << u << " = " << w << "[(j + " << u << ") * " << n_in
        << " + i];\n";
    }
    o << "        CNN_CF_IVDEP\n"
      << "        for (l = 0; l < n; ++l) {\n";
    for (int u = 0; u < units; ++u) o << "          s" << u << "[l] += w" << u << " * x[l];\n";
    o << "        }\n"
      << "      }\n"
      << "      CNN_CF_IVDEP\n"
      << "      for (l = 0; l < n; ++l) {\n";
    for (int u = 0; u < units; ++u) {
      o << "        " << y << "[(j + " << u << ") * n + l] = " << sigmoid << "(s" << u << "[l], " << p
        << "_gain);\n";
    }
    o << "      }\n"
      << "    }\n";
  }
}

// The forward pass over n lanes, in the network's real type (lib/search's forward_pass, network_block.hpp):
// the same operations in the same order, so that each lane rounds as the library's. `one`: the pass of one
// query (p_forward_one), whose layers run across the units instead of the lanes (transposed weights,
// p_w<l>t): the same sums in the same order for each unit, so the same bits as a lane of the block pass;
// the block pass with n = 1 ran every unit's chain as a loop of one lane (gregory-48: 600 ns a query, the
// rest of the query 180).
template <class Net>
void forward_pass(std::ostringstream& o, const NetworkModel& m, const std::string& p, bool one) {
  constexpr bool kFloat = std::is_same_v<Net, float>;
  const std::string net = kFloat ? "float" : "double";
  const std::string sigmoid = kFloat ? "cnn_sigmoidf" : "cnn_sigmoid";
  const std::string block = one ? std::string("1") : p + "_block_lanes";
  const auto& sizes = m.layer_sizes();
  const int n_features = sizes[0];
  forward_opening(o, m, p, one, net, block);
  if (m.input_features() == InputFeatures::kAffine) affine_features(o, m, block);
  o << "  for (i = 0; i < " << n_features << "; ++i) {\n"
    << "    const " << net << " lo = (" << net << ")" << p << "_input_min[i], gain = (" << net << ")" << p
    << "_input_gain[i];\n"
    << "    CNN_CF_IVDEP\n"
    << "    for (l = 0; l < n; ++l) {\n"
    << "      " << net << " x = ((" << net << ")in[i * n + l] - lo) * gain - (" << net << ")1;\n"
    << "      x = x > (" << net << ")1e6 ? (" << net << ")1e6 : x;\n"
    << "      x = x < (" << net << ")-1e6 ? (" << net << ")-1e6 : x;\n"
    << "      a0[i * n + l] = x;\n"
    << "    }\n"
    << "  }\n";
  for (int layer = 0; layer < m.layer_count(); ++layer) {
    const int n_in = sizes[static_cast<std::size_t>(layer)],
              n_out = sizes[static_cast<std::size_t>(layer) + 1];
    const std::string w = p + "_w" + std::to_string(layer), theta = p + "_theta" + std::to_string(layer);
    const std::string x = "a" + std::to_string(layer), y = "a" + std::to_string(layer + 1);
    o << "  { /* layer " << layer + 1 << ": " << n_out << " units of " << n_in << " inputs */\n"
      << "    int j;\n";
    if (one) {
      layer_one(o, net, sigmoid, p, n_in, n_out, w, theta, x, y);
      continue;
    }
    layer_block(o, net, sigmoid, p, block, n_in, n_out, w, theta, x, y);
    o << "  }\n";
  }
  const std::string last = "a" + std::to_string(m.layer_count());
  o << "  for (i = 0; i < 2; ++i) {\n"
    << "    const double lo = " << p << "_output_min[i], inverse_gain = " << p << "_output_inverse_gain[i];\n"
    << "    CNN_CF_IVDEP\n"
    << "    for (l = 0; l < n; ++l) est[i * n + l] = lo + ((double)" << last << "[i * n + l] - "
    << literal(m.target_low()) << ") * inverse_gain;\n"
    << "  }\n"
    << "}\n\n";
}

template <class Net>
void parameter_tables(std::ostringstream& o, const NetworkModel& m, const std::string& p) {
  const std::string net = std::is_same_v<Net, float> ? "float" : "double";
  const auto& sizes = m.layer_sizes();
  for (int l = 0; l < m.layer_count(); ++l) {
    const auto n_in = static_cast<std::size_t>(sizes[static_cast<std::size_t>(l)]);
    const auto n_out = static_cast<std::size_t>(sizes[static_cast<std::size_t>(l) + 1]);
    o << "/* Layer " << l + 1 << ": W (" << n_out << " units x " << n_in
      << " inputs, row-major) and theta. */\n";
    table(o, net, p + "_w" + std::to_string(l), m.weights<Net>(l), n_out * n_in, n_in);
    // NetworkModel's transposed copy (the library's one-query pass), without its padding units.
    const Net* padded = m.transposed_weights<Net>(l);
    const auto stride = static_cast<std::size_t>(m.padded_units(l));
    std::vector<Net> transposed;
    for (std::size_t i = 0; i < n_in; ++i) {
      transposed.insert(transposed.end(), padded + i * stride, padded + i * stride + n_out);
    }
    o << "/* The same W transposed (" << n_in << " inputs x " << n_out
      << " units), for the one-query pass. */\n";
    table(o, net, p + "_w" + std::to_string(l) + "t", transposed.data(), n_out * n_in, n_out);
    table(o, net, p + "_theta" + std::to_string(l), m.thresholds<Net>(l), n_out, 8);
  }
  o << "/* 2 / U0 (Eq 12). */\n"
    << "static const " << net << " " << p << "_gain = " << literal(m.gain<Net>()) << ";\n";
}

// The names every part of a header uses.
struct HeaderNames {
  std::string p;       // the prefix
  bool gregory;        // Gregory patch (else bilinear facet)
  int n_raw;           // columns of a raw query
  std::string block;   // the lanes-per-block constant
  std::string g;       // the C kernels' Gregory flag, "1" or "0"
  std::string centre;  // the parameter domain's centre
  bool float_frame;    // the bilinear float frame (cnn_cff_*) with its double fallback
  bool check_domain;   // the training domain is tested
};

HeaderNames header_names(const NetworkModel& m, const CHeaderOptions& options) {
  const bool gregory = m.surface() == SurfaceKind::kGregory;
  return {options.prefix,           gregory,
          gregory ? 27 : 15,        options.prefix + "_block_lanes",
          gregory ? "1" : "0",      gregory ? "0.5" : "0.0",
          !gregory && m.is_float(), options.check_domain};
}

// 1. What it is and how to call it.
void header_comment(std::ostringstream& o, const NetworkModel& m, const CHeaderOptions& options,
                    const HeaderNames& h, const std::string& guard) {
  const std::string& p = h.p;
  const bool gregory = h.gregory;
  const int n_raw = h.n_raw;
  const std::string real = m.is_float() ? "float" : "double";
  o << "/* Generated by contactnn (search::export_c_header; train-net --export-header). Do not edit: "
       "regenerate\n"
    << " * from the network file.\n"
    << " * " << (options.description.empty() ? std::string("contactnn network") : options.description) << "\n"
    << " * " << to_string(m.surface()) << " segment; sigmoid network";
  for (std::size_t l = 0; l < m.layer_sizes().size(); ++l) o << (l ? "-" : " ") << m.layer_sizes()[l];
  o << ", computed in " << real << ", " << (m.input_features() == InputFeatures::kAffine ? "affine" : "paper")
    << " input features; training domain " << (options.check_domain ? "checked" : "not checked") << ".\n"
    << " *\n"
    << " *   int " << p << "_local_coordinates(const double raw[" << n_raw << "], double out[2]);\n"
    << " *   void " << p
    << "_local_coordinates_batch(size_t n, const double* raw, double* out, int* status);\n"
    << " *\n"
    << " * raw: ax ay az bx by bz cx cy cz dx dy dz sx sy sz (world coordinates of the segment's nodes A, "
       "B, "
       "C, D\n"
    << " * counter-clockwise, and of the slave node S"
    << (gregory ? "), then the node normals nax nay naz ... ndz (any\n"
                  " * positive length"
                : "")
    << "), in any node order.\n"
    << " * out: " << (gregory ? "(u, v) in [0, 1]^2" : "(xi, eta) in [-1, 1]^2")
    << ", the network's estimate of the closest point, in the caller's node order.\n"
    << " * Returns 0 on success, 1 for a non-finite input or a degenerate segment (out untouched), 2 when "
       "the\n"
    << " * canonical configuration lies outside the network's training domain (out is written, but it is "
       "an\n"
    << " * extrapolation). The batch: n queries, raw n x " << n_raw
    << " and out n x 2 row-major, status[i] the\n"
    << " * code query i would return alone (rows of status 1 untouched).\n"
    << " *\n"
    << " * Each query is contactnn's LocalSearch method \"network\", computed by the same C99 kernels "
       "(embedded\n"
    << " * below, verbatim): the canonical configuration of SPEC 4 (relabelling, frame, z orientation); on "
       "a "
       "tie\n"
    << " * (a slave as near two nodes, ...) the mean over every tied canonical form, so that the answer "
       "does "
       "not\n"
    << " * depend on the node order; the input scaling; the forward pass; the domain test of\n"
    << " * TrainingDomain::contains (feature ranges and the generator's filters).\n"
    << " * The batch runs blocks of " << kBlockLanes
    << " queries through loops over the queries that GCC and Clang vectorise at\n"
    << " * -O3 given -fno-math-errno -fno-trapping-math (neither changes a result; without them the same "
       "code runs\n"
    << " * scalar). Its results are those of the one-query function bit for bit where the compiler does "
       "not\n"
    << " * contract multiply-adds (ISO C modes such as -std=c99, or -ffp-contract=off); with contraction "
       "(GNU\n"
    << " * modes, C++) the vectorised and the one-query code contract differently: the same to the "
       "rounding "
       "of\n"
    << " * the network's precision (" << real << ").\n";
  if (!gregory && m.is_float()) {
    o << " * After a block whose lanes the float frame mostly cannot decide (touching contact: slaves on "
         "the\n"
      << " * master's plane; square elements), the batch runs the frame in double first for the next (the "
         "same\n"
      << " * results, faster on real decks); the one-query function guesses the order from the query "
         "itself\n"
      << " * (cnn_cff_looks_undecided: a slave on the plane of A, B, D or a square corner at A).\n";
  }
  o << " * C99, or C++11 and later; two headers with different prefixes can share a translation unit.\n"
    << " * Link with -lm. Not for -ffast-math: it drops the NaN tests (a non-finite input is no longer\n"
    << " * status 1) and reorders the sums on which the batch's bit-for-bit agreement with the one-query\n"
    << " * function rests.\n"
    << " */\n"
    << "#ifndef " << guard << "\n#define " << guard << "\n\n#include <math.h>\n#include <stddef.h>\n\n";
}

// 2. lib/search's kernels, verbatim, and the check that they are the ones in force.
void embedded_kernels(std::ostringstream& o, const std::string& p) {
  const std::string_view frame = canonical_frame_source();
  const std::string_view sigmoid = vector_sigmoid_source();
  const std::string frame_version = macro_value(frame, "CNN_CANONICAL_FRAME_VERSION");
  const std::string sigmoid_version = macro_value(sigmoid, "CNN_VECTOR_SIGMOID_VERSION");
  o << "/* ======== lib/search/canonical_frame.h and its parts, verbatim ======== */\n"
    << frame << "\n/* ======== lib/search/vector_sigmoid.h, verbatim ======== */\n"
    << sigmoid << "\n"
    << "/* ======== the network ======== */\n"
    << "#if CNN_CANONICAL_FRAME_VERSION != " << frame_version
    << " || CNN_VECTOR_SIGMOID_VERSION != " << sigmoid_version << "\n#error \"" << p
    << ": a header included earlier in this translation unit brought other versions of canonical_frame.h "
       "or "
    << "vector_sigmoid.h; regenerate the exported headers with one contactnn\"\n#endif\n\n";
}

// 3. Tables: parameters, scaling, domain.
void tables(std::ostringstream& o, const NetworkModel& m, const HeaderNames& h) {
  const std::string& p = h.p;
  const cnn_domain& d = m.domain_bounds();
  if (m.is_float()) {
    parameter_tables<float>(o, m, p);
  } else {
    parameter_tables<double>(o, m, p);
  }
  o << "/* Input scaling x_s = (x - min) gain - 1, output t = min + (o - target_low) inverse_gain "
       "(mlp::Scaling). */\n";
  table(o, "double", p + "_input_min", m.input_min().data(), m.input_min().size(), 4);
  table(o, "double", p + "_input_gain", m.input_gain().data(), m.input_gain().size(), 4);
  table(o, "double", p + "_output_min", m.output_min().data(), m.output_min().size(), 4);
  table(o, "double", p + "_output_inverse_gain", m.output_inverse_gain().data(),
        m.output_inverse_gain().size(), 4);
  if (h.check_domain) {
    o << "/* The training domain as cnn_domain_lane tests it (search::domain_bounds). */\n"
      << "static const struct cnn_domain " << p << "_domain = {\n";
    // Positional, each field named in a comment (struct cnn_domain's order): designated initializers are
    // C99 but C++ only from C++20, and an FE code in C++17 includes this header too.
    auto row = [&](const char* name, const double* v, int n) {
      o << "  /* " << name << " */ {";
      for (int i = 0; i < n; ++i) {
        CONTACTNN_REQUIRE(!std::isnan(v[i]), "domain bound " << name << "[" << i << "] is NaN");
        o << (i ? ", " : "") << literal(v[i]);
      }
      o << "},\n";
    };
    row("lo", d.lo, 16);
    row("hi", d.hi, 16);
    o << "  /* xy */ " << literal(d.xy) << ", /* z */ " << literal(d.z) << ", /* ad_bound */ "
      << literal(d.ad_bound) << ", /* inv_one_plus_tol */ " << literal(d.inv_one_plus_tol) << ",\n"
      << "  /* tol */ " << literal(d.tol) << ", /* cos_lo */ " << literal(d.cos_lo) << ", /* cos_hi */ "
      << literal(d.cos_hi) << ", /* tilt */ " << literal(d.tilt) << ",\n"
      << "  /* features */ " << d.features << ", /* ad_not_longer */ " << d.ad_not_longer
      << ", /* nearest_a */ " << d.nearest_a << ", /* segment_test */ " << d.segment_test << ", /* convex */ "
      << d.convex << ",\n"
      << "  /* check_lo */ " << d.check_lo << ", /* check_hi */ " << d.check_hi << "};\n";
  }
  o << "\nenum { " << h.block << " = " << kBlockLanes << " };\n\n";
}

// 5. Ties: lib/search's tie_estimate (kernels_single.cpp).
void tie_function(std::ostringstream& o, const NetworkModel& m, const HeaderNames& h) {
  const std::string &p = h.p, &g = h.g, &centre = h.centre;
  const cnn_domain& d = m.domain_bounds();
  const bool angles = d.check_lo != 0 || d.check_hi != 0;
  o << "/* A query on a tie: the mean over its canonical forms in the domain (cnn_cf_forms, in\n"
    << " * geometry::canonical_forms' order) of the network's estimate in the caller's node order; when no "
       "form is\n"
    << " * in the domain, the mean over every form, out of the domain. */\n"
    << "static inline void " << p
    << "_tie(const double* CNN_CF_RESTRICT x, double* u, double* v, double* code) {\n"
    << "  double f[16 * CNN_CF_MAX_FORMS], nrm[12 * CNN_CF_MAX_FORMS], info[CNN_CF_INFO_ROWS * "
       "CNN_CF_MAX_FORMS];\n"
    << "  double all_u = 0.0, all_v = 0.0, in_u = 0.0, in_v = 0.0, inside = 0.0;\n"
    << "  int k;\n"
    << "  const int count = cnn_cf_forms(x, " << g << ", f, nrm, info);\n"
    << "  if (info[0] != (double)CNN_CF_STATUS_OK) return;\n"
    << "  for (k = 0; k < count; ++k) {\n"
    << "    double e[2], c = (double)CNN_CF_STATUS_OK;\n";
  if (h.check_domain) {
    o << "    cnn_domain_lane(&" << p << "_domain, " << g << ", " << (angles ? 1 : 0)
      << ", f + 16 * k, nrm + 12 * k, 1, &c);\n";
  }
  o << "    " << p << "_forward_one(f + 16 * k, e);\n"
    << "    cnn_cf_to_caller(info[CNN_CF_INFO_ROWS * k + 1], " << centre << ", &e[0], &e[1]);\n"
    << "    all_u += e[0];\n"
    << "    all_v += e[1];\n"
    << "    if (c == (double)CNN_CF_STATUS_OK) {\n"
    << "      in_u += e[0];\n"
    << "      in_v += e[1];\n"
    << "      inside += 1.0;\n"
    << "    }\n"
    << "  }\n"
    << "  *u = inside > 0.0 ? in_u / inside : all_u / count;\n"
    << "  *v = inside > 0.0 ? in_v / inside : all_v / count;\n"
    << "  *code = inside > 0.0 ? (double)CNN_CF_STATUS_OK : (double)CNN_CF_STATUS_OUT_OF_DOMAIN;\n"
    << "}\n\n";
}

// 5b. The tie lanes of a block: lib/search's tie_estimates_block (the forms of all tie lanes, a block at a
// time). First the forms, kBlockLanes at a time.
void forms_function(std::ostringstream& o, const HeaderNames& h) {
  const std::string &p = h.p, &g = h.g, &centre = h.centre, &block = h.block;
  const std::string domain_arg = h.check_domain ? "&" + p + "_domain" : std::string();
  o << "/* count <= " << kBlockLanes << " forms (rows in `in`, " << kBlockLanes
    << " lanes, the empty slots copies of the first) with\n"
    << " * symmetry sym and z orientation zo forced: each form's estimate in the caller's order, whether "
       "it "
       "exists,\n"
    << " * whether it lies in the domain. */\n"
    << "static void " << p
    << "_forms(int count, const double* CNN_CF_RESTRICT in, const int* CNN_CF_RESTRICT sym,\n"
    << "                        const int* CNN_CF_RESTRICT zo, double* CNN_CF_RESTRICT x, double* "
       "CNN_CF_RESTRICT y,\n"
    << "                        int* CNN_CF_RESTRICT valid, int* CNN_CF_RESTRICT inside) {\n"
    << "  double f[16 * " << block << "], nrm[12 * " << block << "], info[CNN_CF_INFO_ROWS * " << block
    << "], e[2 * " << block << "];\n"
    << "  int s;\n"
    << "  CNN_CF_IVDEP\n"
    << "  for (s = 0; s < " << block << "; ++s) cnn_cf_lane(in + s, " << block << ", " << g
    << ", 1, sym[s], zo[s], f + s, nrm + s, info + s, " << block << ");\n"
    << "  for (s = 0; s < count; ++s) {\n"
    << "    if (info[4 * " << block << " + s] != 0.0) {\n"
    << "      cnn_cf_lane_scaled(in + s, " << block << ", " << g
    << ", 1, sym[s], zo[s], f + s, nrm + s, info + s, " << block << ");\n"
    << "    }\n"
    << "    valid[s] = info[s] == (double)CNN_CF_STATUS_OK;\n"
    << "  }\n";
  if (h.check_domain)
    o << "  cnn_domain_block(" << block << ", " << g << ", " << domain_arg << ", f, nrm, info);\n";
  o << "  " << p << "_forward(" << block << ", f, e);\n"
    << "  for (s = 0; s < count; ++s) {\n"
    << "    x[s] = e[s];\n"
    << "    y[s] = e[" << block << " + s];\n"
    << "    cnn_cf_to_caller(info[" << block << " + s], " << centre << ", &x[s], &y[s]);\n"
    << "    inside[s] = info[s] == (double)CNN_CF_STATUS_OK;\n"
    << "  }\n"
    << "}\n\n";
}

// 5b. Then the tie lanes of a block, through the forms.
void ties_function(std::ostringstream& o, const HeaderNames& h) {
  const std::string &p = h.p, &block = h.block, &g = h.g;
  const int n_raw = h.n_raw;
  o << "/* The tie lanes of a block of n > 1 lanes (lanes[0 .. n_ties - 1]; raw: the block's rows; info: "
       "its info\n"
    << " * rows): what " << p
    << "_tie gives each, with form 0 the block's own estimate (u, v, code of the lane) and\n"
    << " * the other forms (cnn_cf_symmetries, and on a Gregory z tie each orientation of z, in "
       "cnn_cf_forms' order)\n"
    << " * computed " << kBlockLanes << " at a time through the batch's forward pass, summed in the order "
    << p << "_tie sums\n"
    << " * them. */\n"
    << "static void " << p
    << "_ties(int n, const double* CNN_CF_RESTRICT raw, const double* CNN_CF_RESTRICT info,\n"
    << "                       const int* CNN_CF_RESTRICT lanes, int n_ties, double* CNN_CF_RESTRICT u,\n"
    << "                       double* CNN_CF_RESTRICT v, double* CNN_CF_RESTRICT code) {\n"
    << "  enum { max_forms = CNN_CF_MAX_FORMS * " << block << " };\n"
    << "  double in[" << n_raw << " * " << block << "], x[max_forms], y[max_forms];\n"
    << "  double all_u[" << block << "], all_v[" << block << "], forms[" << block << "], in_u[" << block
    << "], in_v[" << block << "], inside[" << block << "];\n"
    << "  int owner[max_forms], sym[max_forms], zo[max_forms], valid[max_forms], in_domain[max_forms];\n"
    << "  int count = 0, done, t, k, z, c, s;\n"
    << "  for (t = 0; t < n_ties; ++t) {\n"
    << "    const int l = lanes[t];\n"
    << "    const double* q = raw + l * " << n_raw << ";\n"
    << "    int tied_sym[8];\n"
    << "    const int tied = cnn_cf_symmetries(q, tied_sym), sym0 = (int)info[n + l];\n"
    << "    const int z_ties = " << g << " & ((int)info[5 * n + l] >> 1);\n"
    << "    const int in0 = code[l] == (double)CNN_CF_STATUS_OK;\n"
    << "    all_u[t] = 0.0 + u[l];\n"
    << "    all_v[t] = 0.0 + v[l];\n"
    << "    forms[t] = 1.0;\n"
    << "    in_u[t] = 0.0 + (in0 ? u[l] : 0.0);\n"
    << "    in_v[t] = 0.0 + (in0 ? v[l] : 0.0);\n"
    << "    inside[t] = in0 ? 1.0 : 0.0;\n"
    << "    for (k = 0; k < tied; ++k) {\n"
    << "      for (z = 0; z <= z_ties; ++z) {\n"
    << "        if (tied_sym[k] == sym0 && z == 0) continue; /* form 0 */\n"
    << "        owner[count] = t;\n"
    << "        sym[count] = tied_sym[k];\n"
    << "        zo[count] = z;\n"
    << "        ++count;\n"
    << "      }\n"
    << "    }\n"
    << "  }\n"
    << "  for (done = 0; done < count; done += " << block << ") {\n"
    << "    const int m = count - done < " << block << " ? count - done : " << block << ";\n"
    << "    int fs[" << block << "], fz[" << block << "];\n"
    << "    for (s = 0; s < " << block << "; ++s) { /* the empty slots: copies of the first */\n"
    << "      const int from = done + (s < m ? s : 0);\n"
    << "      const double* q = raw + lanes[owner[from]] * " << n_raw << ";\n"
    << "      for (c = 0; c < " << n_raw << "; ++c) in[c * " << block << " + s] = q[c];\n"
    << "      fs[s] = sym[from];\n"
    << "      fz[s] = zo[from];\n"
    << "    }\n"
    << "    " << p << "_forms(m, in, fs, fz, x + done, y + done, valid + done, in_domain + done);\n"
    << "  }\n"
    << "  for (s = 0; s < count; ++s) {\n"
    << "    if (!valid[s]) continue;\n"
    << "    t = owner[s];\n"
    << "    all_u[t] += x[s];\n"
    << "    all_v[t] += y[s];\n"
    << "    forms[t] += 1.0;\n"
    << "    if (in_domain[s]) {\n"
    << "      in_u[t] += x[s];\n"
    << "      in_v[t] += y[s];\n"
    << "      inside[t] += 1.0;\n"
    << "    }\n"
    << "  }\n"
    << "  for (t = 0; t < n_ties; ++t) {\n"
    << "    const int l = lanes[t];\n"
    << "    u[l] = inside[t] > 0.0 ? in_u[t] / inside[t] : all_u[t] / forms[t];\n"
    << "    v[l] = inside[t] > 0.0 ? in_v[t] / inside[t] : all_v[t] / forms[t];\n"
    << "    code[l] = inside[t] > 0.0 ? (double)CNN_CF_STATUS_OK : (double)CNN_CF_STATUS_OUT_OF_DOMAIN;\n"
    << "  }\n"
    << "}\n\n";
}

// 6. A block of n lanes: lib/search's network_estimate.
void block_function(std::ostringstream& o, const HeaderNames& h) {
  const std::string &p = h.p, &block = h.block, &g = h.g, &centre = h.centre;
  const int n_raw = h.n_raw;
  const bool float_frame = h.float_frame;
  o << "/* n <= " << block << " queries (rows of " << n_raw
    << "): canonical frame, domain test, forward pass for all lanes\n"
    << " * at once, then each lane mapped back to the caller's order (ties through " << p << "_tie). */\n"
    << "CNN_CF_INLINE void " << p
    << "_block(int n, const double* CNN_CF_RESTRICT raw, double* CNN_CF_RESTRICT out,\n"
    << "                                  int* CNN_CF_RESTRICT status, int* CNN_CF_RESTRICT expect) {\n"
    << "  double in[" << n_raw << " * " << block << "], f[16 * " << block << "], "
    << (float_frame ? std::string() : "nrm[12 * " + block + "], ") << "info[CNN_CF_INFO_ROWS * " << block
    << "];\n"
    << "  double est[2 * " << block << "];\n"
    << "  int k, l;\n"
    << "  for (l = 0; l < n; ++l) {\n"
    << "    for (k = 0; k < " << n_raw << "; ++k) in[k * n + l] = raw[l * " << n_raw << " + k];\n"
    << "  }\n";
  if (float_frame) {
    // As lib/search's network_estimate for a float network: the frame and domain test in float where float
    // decides them, the other lanes in double (canonical_frame.h), so that the header agrees bit for bit.
    // The batch keeps *expect from block to block (cnn_cff_block_expecting: the double pass first on
    // touching contact; the same bits).
    o << "  cnn_canonicalise_domain_block_fe(n, " << (h.check_domain ? "&" + p + "_domain" : std::string("0"))
      << ", in, f, info, expect);\n";
  } else {
    o << "  (void)expect;\n";
    o << "  cnn_canonicalise_block(n, " << g << ", in, f, nrm, info);\n";
    if (h.check_domain) o << "  cnn_domain_block(n, " << g << ", &" << p << "_domain, f, nrm, info);\n";
  }
  o << "  if (n == 1) {\n"
    << "    " << p << "_forward_one(f, est);\n"
    << "  } else {\n"
    << "    " << p << "_forward(n, f, est);\n"
    << "  }\n"
    << "  {\n"
    << "    /* The lanes mapped to the caller's order; those on a tie then get the mean over their forms. "
       "*/\n"
    << "    double u[" << block << "], v[" << block << "], code[" << block << "];\n"
    << "    int ties[" << block << "], n_ties = 0;\n"
    << "    for (l = 0; l < n; ++l) {\n"
    << "      code[l] = info[l];\n"
    << "      u[l] = est[l];\n"
    << "      v[l] = est[n + l];\n"
    << "      if (code[l] != (double)CNN_CF_STATUS_OK && code[l] != (double)CNN_CF_STATUS_OUT_OF_DOMAIN) "
       "continue;\n"
    << "      cnn_cf_to_caller(info[n + l], " << centre << ", &u[l], &v[l]);\n"
    << "      if (cnn_cf_needs_forms(info[5 * n + l], " << g << ")) ties[n_ties++] = l;\n"
    << "    }\n"
    << "    if (n_ties > 0 && n == 1) {\n"
    << "      " << p << "_tie(raw, &u[0], &v[0], &code[0]);\n"
    << "    } else if (n_ties > 0) {\n"
    << "      " << p << "_ties(n, raw, info, ties, n_ties, u, v, code);\n"
    << "    }\n"
    << "    for (l = 0; l < n; ++l) {\n"
    << "      if (code[l] != (double)CNN_CF_STATUS_OK && code[l] != (double)CNN_CF_STATUS_OUT_OF_DOMAIN) "
       "{\n"
    << "        status[l] = 1;\n"
    << "        continue;\n"
    << "      }\n"
    << "      out[2 * l] = u[l];\n"
    << "      out[2 * l + 1] = v[l];\n"
    << "      status[l] = code[l] == (double)CNN_CF_STATUS_OK ? 0 : 2;\n"
    << "    }\n"
    << "  }\n"
    << "}\n\n";
}

// 7. The entry points.
void entry_points(std::ostringstream& o, const HeaderNames& h, const std::string& guard) {
  const std::string &p = h.p, &block = h.block;
  const int n_raw = h.n_raw;
  const bool float_frame = h.float_frame;
  // A float network's bilinear query that looks like touching contact or a square takes the double pass
  // first (cnn_cff_looks_undecided; the same result).
  o << "static inline int " << p << "_local_coordinates(const double raw[" << n_raw << "], double out[2]) {\n"
    << "  int status" << (float_frame ? ", expect = cnn_cff_looks_undecided(raw, 1)" : "") << ";\n"
    << "  " << p << "_block(1, raw, out, &status, " << (float_frame ? "&expect" : "0") << ");\n"
    << "  return status;\n"
    << "}\n\n"
    << "/* Blocks of " << block
    << " queries; the last, partial block padded with copies of its last query. */\n"
    << "static inline void " << p
    << "_local_coordinates_batch(size_t n, const double* raw, double* out, int* status) {\n"
    << "  size_t i = 0;\n"
    << "  int expect = 0;\n"
    << "  for (; i + " << block << " <= n; i += " << block << ") {\n"
    << "    " << p << "_block(" << block << ", raw + i * " << n_raw
    << ", out + 2 * i, status + i, &expect);\n"
    << "  }\n"
    << "  if (i < n) {\n"
    << "    double pad[" << block << " * " << n_raw << "], pad_out[2 * " << block << "];\n"
    << "    int pad_status[" << block << "], l, k;\n"
    << "    const int rest = (int)(n - i);\n"
    << "    for (l = 0; l < " << block << "; ++l) {\n"
    << "      const double* row = raw + (i + (size_t)(l < rest ? l : rest - 1)) * " << n_raw << ";\n"
    << "      for (k = 0; k < " << n_raw << "; ++k) pad[l * " << n_raw << " + k] = row[k];\n"
    << "    }\n"
    << "    " << p << "_block(" << block << ", pad, pad_out, pad_status, &expect);\n"
    << "    for (l = 0; l < rest; ++l) {\n"
    << "      status[i + l] = pad_status[l];\n"
    << "      if (pad_status[l] == 1) continue;\n"
    << "      out[2 * (i + l)] = pad_out[2 * l];\n"
    << "      out[2 * (i + l) + 1] = pad_out[2 * l + 1];\n"
    << "    }\n"
    << "  }\n"
    << "}\n\n"
    << "#endif /* " << guard << " */\n";
}

}  // namespace

std::string export_c_header(const NetworkModel& m, const CHeaderOptions& options) {
  CONTACTNN_REQUIRE_AS(InvalidArgument, is_c_identifier(options.prefix),
                       "the C header's prefix '" << options.prefix << "' is not a C identifier");
  const HeaderNames h = header_names(m, options);
  std::string guard = h.p + "_H";
  for (char& c : guard) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::ostringstream o;
  header_comment(o, m, options, h, guard);
  embedded_kernels(o, h.p);
  tables(o, m, h);
  // 4. The forward pass.
  for (const bool one : {false, true}) {
    if (m.is_float()) {
      forward_pass<float>(o, m, h.p, one);
    } else {
      forward_pass<double>(o, m, h.p, one);
    }
  }
  tie_function(o, m, h);
  forms_function(o, h);
  ties_function(o, h);
  block_function(o, h);
  entry_points(o, h, guard);
  return o.str();
}

}  // namespace contactnn::search
