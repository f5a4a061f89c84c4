// Progress lines: the one callback type through which the studies and the method comparison report what they
// are doing (a tool prints each line; a test or a quiet run passes an empty one, and nothing is said).
#pragma once

#include <functional>
#include <string_view>

namespace contactnn {

/// Called with one line of progress, without its line break; an empty ProgressLog says nothing.
using ProgressLog = std::function<void(std::string_view)>;

}  // namespace contactnn
