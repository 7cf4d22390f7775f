// libFuzzer target: the pipeline reader (JSON syntax, the hand checker, every task kind's
// parse), then the run itself with inline samples, its output thrown away. Plugins are loaded
// once. The run is given one thread so that a finding reproduces exactly.
#include <optional>
#include <string_view>

#include "fuzz_support.h"
#include "imuconv/pipeline/pipeline.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace imuconv;
  static fuzz::InputFile file("pipeline.json");
  const Registry& reg = fuzz::LoadedRegistry();
  const std::string& path = file.write(data, size);
  // Reading the pipeline: its errors name the pipeline file. Running it: an error names the
  // file at fault, which may be another one the pipeline names (an IMU file that is missing).
  std::optional<pipeline::Pipeline> p;
  fuzz::Expect([&] { p.emplace(pipeline::Pipeline::Load(path)); }, path);
  if (!p) return 0;
  fuzz::Expect(
      [&] {
        pipeline::RunOptions options;
        options.threads = 1;
        pipeline::RunToText(*p, reg, options, [](std::string_view) {});
      },
      "");
  return 0;
}
