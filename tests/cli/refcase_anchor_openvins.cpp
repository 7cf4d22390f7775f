// OpenVINS's rule for `imuconv refcase --anchor openvins` against its anchor files
// (refcase_anchor.cpp runs it before the generic comparison, refcase_anchor.h): a method is
// compared when its propagator is registered (`openvins_discrete` always is), and the output's
// methods_written must name exactly those.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "imuconv_test.h"
#include "refcase_anchor.h"

namespace {
using namespace imuconv::test;
using namespace imuconv::test::refcase_anchor;
using nlohmann::json;

void OpenVinsRegisteredMethods(json& anchor, json& out, const std::string& label, FieldWorst&) {
  json expected = json::array();
  for (const auto& [key, plugin] :
       {std::pair<const char*, const char*>{"discrete", "openvins_discrete"},
        {"rk4", "openvins_rk4"},
        {"analytical", "openvins_analytical"}}) {
    if (Plugins().has(imuconv::PluginKind::Propagator, plugin))
      expected.push_back(plugin);
    else
      anchor.erase(key);  // not computable here: reported by the output, not compared
  }
  ASSERT_EQ(out.at("methods_written"), expected) << label;
  ASSERT_TRUE(anchor.contains("discrete")) << label;
}

IMUCONV_REFCASE_ANCHOR_RULE(openvins, "openvins", &OpenVinsRegisteredMethods);

}  // namespace
