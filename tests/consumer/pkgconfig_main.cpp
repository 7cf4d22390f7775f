// Built with `pkg-config --cflags --libs imuconv` alone (no CMake): loads the installed
// plugins and checks that a derived conversion inverts its reverse.
#include <imuconv/registry.h>
#include <imuconv/so3.h>

#include <cstdio>

int main() {
  using namespace imuconv;
  Registry reg;
  for (const auto& issue : reg.load_search_path())
    std::fprintf(stderr, "%s: %s\n", issue.file.c_str(), issue.message.c_str());
  ImuState x;
  x.R = so3::Exp(Vec3(0.4, -0.3, 1.2));
  x.p = Vec3(3, -1, 2);
  x.v = Vec3(1, 2, 3);
  // Both directions are derived from the plugins' analytic Jacobians: the product is I to
  // round-off (~1e-15); 1e-12 leaves room and catches any wrong block.
  const double e_inv =
      (reg.conversion("left", "gtsam_navstate", x) * reg.conversion("gtsam_navstate", "left", x) -
       Mat15::Identity())
          .cwiseAbs()
          .maxCoeff();
  std::printf("pkg-config consumer: %zu plugins, J*J^-1 - I %.2e\n", reg.plugins().size(), e_inv);
  return (reg.plugins().size() > 10 && e_inv < 1e-12) ? 0 : 1;
}
