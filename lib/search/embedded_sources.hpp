// The C99 kernels of lib/search as text, for the exported C header of a network (search::export_c_header
// embeds them verbatim, so that the header and the library canonicalise with one source).
#pragma once

#include <string_view>

namespace contactnn::search {

/// The full text of canonical_frame.h (the canonical configuration and the training-domain test).
[[nodiscard]] std::string_view canonical_frame_source();
/// The full text of vector_sigmoid.h (exp and the sigmoid of Eq 12, vectorisable).
[[nodiscard]] std::string_view vector_sigmoid_source();

}  // namespace contactnn::search
