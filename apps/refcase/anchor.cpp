// imuconv refcase --anchor (see anchor.h): the table of anchor writers, one file each in
// anchors/ (anchors/anchor_writer.h), listed by CMake into anchor_table.inc.
#include "anchor.h"

#include <algorithm>

#include "anchors/anchor_writer.h"
#include "imuconv/printable.h"

namespace imuconv::refcase {

#define IMUCONV_ANCHOR(STEM) const AnchorWriter& STEM##_anchor_writer();
#include "anchor_table.inc"
#undef IMUCONV_ANCHOR

namespace {

using json = nlohmann::json;

const std::vector<const AnchorWriter*>& Writers() {
#define IMUCONV_ANCHOR(STEM) &STEM##_anchor_writer(),
  static const std::vector<const AnchorWriter*> writers = {
#include "anchor_table.inc"
  };
#undef IMUCONV_ANCHOR
  return writers;
}

}  // namespace

const std::vector<std::string>& AnchorNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const AnchorWriter* w : Writers()) n.emplace_back(w->name);
    return n;
  }();
  return names;
}

json RunAnchor(const Registry& reg, const json& case_json, const std::string& name) {
  const auto& writers = Writers();
  const auto it = std::find_if(writers.begin(), writers.end(),
                               [&](const AnchorWriter* w) { return name == w->name; });
  if (it == writers.end()) {
    std::string known;
    for (const std::string& n : AnchorNames()) known += (known.empty() ? "" : ", ") + n;
    throw Error("--anchor: unknown anchor '" + Printable(name) + "'; expected one of " + known);
  }
  const Case k = ParseCase(case_json);
  json out = (*it)->write(reg, k);
  out["case_id"] = case_json.contains("case_id") ? case_json.at("case_id") : json("");
  out["anchor"] = name;
  out["generator"] = "imuconv refcase --anchor";
  CheckResults(out, "");
  return out;
}

}  // namespace imuconv::refcase
