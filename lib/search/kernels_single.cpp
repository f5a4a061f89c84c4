// The one-lane instantiations of the block kernels, for queries outside whole blocks, and the scalar path of
// queries on a tie. This file is compiled without auto-vectorisation (see CMakeLists.txt and
// select_single_kernels in search_kernel.hpp), once per instruction-set variant like the block kernels
// (isa_dispatch.hpp): each variant's select_bilinear_kernels and select_gregory_kernels call this file's
// select_single_kernels of the same variant (its symbols are the variant's own, with the variant's suffix),
// so a query alone rounds as in a block of that variant.
#include "geometry/affine_frame.hpp"
#include "geometry/segment_checks.hpp"
#include "search/search_kernel.hpp"

namespace contactnn::search::detail {

void select_single_kernels(Plan& plan) {
  const bool float_network =
      plan.method.needs_network() && plan.network != nullptr && plan.network->is_float();
  if (plan.kind == SurfaceKind::kGregory) {
    plan.single_f =
        float_network ? &search_block<true, float, 1, float> : &search_block<true, double, 1, float>;
    plan.single_d =
        float_network ? &search_block<true, float, 1, double> : &search_block<true, double, 1, double>;
  } else {
    plan.single_f =
        float_network ? &search_block<false, float, 1, float> : &search_block<false, double, 1, float>;
    plan.single_d =
        float_network ? &search_block<false, float, 1, double> : &search_block<false, double, 1, double>;
  }
}

template <class Net, bool kGregory>
void tie_estimate(const NetworkModel& m, bool check_domain, const double* query, double& u, double& v,
                  double& status) {
  constexpr int kG = kGregory ? 1 : 0;
  double f[16 * CNN_CF_MAX_FORMS], nrm[12 * CNN_CF_MAX_FORMS], info[CNN_CF_INFO_ROWS * CNN_CF_MAX_FORMS];
  const int count = cnn_cf_forms(query, kG, f, nrm, info);
  if (info[0] != kOk) return;  // the block pass's form 0 is ok; the same code cannot say otherwise
  const cnn_domain& d = m.domain_bounds();
  const int angles = d.check_lo | d.check_hi;
  const double centre = kGregory ? 0.5 : 0.0;
  // Two sums in geometry::canonical_forms' order: over every form, and over the forms in the domain.
  double all_u = 0.0, all_v = 0.0, in_u = 0.0, in_v = 0.0, inside = 0.0;
  for (int k = 0; k < count; ++k) {
    const double* fk = f + 16 * k;
    double code = kOk;
    if (check_domain) cnn_domain_lane(&d, kG, angles, fk, nrm + 12 * k, 1, &code);
    double out[2];
    forward_pass<Net, 1>(m, fk, out);
    cnn_cf_to_caller(info[CNN_CF_INFO_ROWS * k + 1], centre, &out[0], &out[1]);
    all_u += out[0];
    all_v += out[1];
    if (code == kOk) {
      in_u += out[0];
      in_v += out[1];
      inside += 1.0;
    }
  }
  const bool any = inside > 0.0;
  u = any ? in_u / inside : all_u / count;
  v = any ? in_v / inside : all_v / count;
  status = any ? kOk : kOutOfDomain;
}

bool degenerate_as_labelled(const double* query, bool gregory) {
  geometry::Configuration c;
  for (std::size_t i = 0; i < 4; ++i) {
    c.nodes[i] = geometry::Vec3(query[3 * i], query[3 * i + 1], query[3 * i + 2]);
    if (gregory) c.normals[i] = geometry::Vec3(query[15 + 3 * i], query[16 + 3 * i], query[17 + 3 * i]);
  }
  c.slave = geometry::Vec3(query[12], query[13], query[14]);
  const geometry::NormaliseOutcome n =
      geometry::normalise(c, gregory ? SurfaceKind::kGregory : SurfaceKind::kBilinear);
  return !n.value || geometry::is_degenerate_segment(n.value->config.nodes);
}

template void tie_estimate<float, false>(const NetworkModel&, bool, const double*, double&, double&, double&);
template void tie_estimate<float, true>(const NetworkModel&, bool, const double*, double&, double&, double&);
template void tie_estimate<double, false>(const NetworkModel&, bool, const double*, double&, double&,
                                          double&);
template void tie_estimate<double, true>(const NetworkModel&, bool, const double*, double&, double&, double&);

}  // namespace contactnn::search::detail
