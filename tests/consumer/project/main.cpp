// Loads the installed plugins and the project's own, and checks one derived conversion.
#include <imuconv/registry.h>
#include <imuconv/so3.h>

#include <cstdio>

int main() {
  using namespace imuconv;
  Registry reg;
  for (const auto& issue : reg.load_search_path())
    std::fprintf(stderr, "%s: %s\n", issue.file.c_str(), issue.message.c_str());
  try {
    reg.load_file(CONSUMER_PLUGIN);
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  ImuState x;
  x.R = so3::Exp(Vec3(0.4, -0.3, 1.2));
  x.v = Vec3(1, 2, 3);
  // left -> body_velocity: dtheta_body = R^T dtheta_left, dv_body = R^T dv_left (derived by
  // the registry from the plugin's retract/local alone). Ridders' differences: ~1e-12.
  const Mat15 J = reg.conversion("left", "body_velocity", x);
  const double e_rot = (J.block<3, 3>(0, 3) - x.R.transpose()).cwiseAbs().maxCoeff();
  const double e_vel = (J.block<3, 3>(6, 6) - x.R.transpose()).cwiseAbs().maxCoeff();
  const double e_inv =
      (J * reg.conversion("body_velocity", "left", x) - Mat15::Identity()).cwiseAbs().maxCoeff();
  std::printf(
      "plugins: %zu, rotation block error %.2e, velocity block error %.2e, J*J^-1 - I %.2e\n",
      reg.plugins().size(), e_rot, e_vel, e_inv);
  return (reg.plugins().size() > 10 && e_rot < 1e-10 && e_vel < 1e-10 && e_inv < 1e-10) ? 0 : 1;
}
