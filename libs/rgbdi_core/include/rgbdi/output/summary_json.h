// The run summary (summary.json). Its content is assembled by the callers (system, eval).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "rgbdi/common/atomic_file.h"  // IoError

namespace rgbdi::output {

/// Pretty-printed (2-space indent, trailing newline), atomic. NaN/inf numbers become null.
/// Throws IoError when the file cannot be written.
void writeSummaryJson(const std::string& path, const nlohmann::json& summary);

}  // namespace rgbdi::output
