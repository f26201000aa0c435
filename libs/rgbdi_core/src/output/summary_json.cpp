#include "rgbdi/output/summary_json.h"

#include "rgbdi/common/atomic_file.h"

namespace rgbdi::output {
namespace {
constexpr int kIndent = 2;
}  // namespace

void writeSummaryJson(const std::string& path, const nlohmann::json& summary) {
  // Serialise first so that a dump error (invalid UTF-8) never leaves a partial temporary behind.
  const std::string text = summary.dump(kIndent);
  writeFileAtomically(path, [&](std::ostream& os) { os << text << '\n'; });
}

}  // namespace rgbdi::output
