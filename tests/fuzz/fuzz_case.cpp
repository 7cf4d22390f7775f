// libFuzzer target: the state reader and the reference-case runner (the case format of
// tests/data/reference/FORMAT.md). The first byte picks which.
#include "fuzz_support.h"
#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_parse.h"
#include "refcase.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace imuconv;
  static fuzz::InputFile file("case.json");
  const Registry& reg = fuzz::LoadedRegistry();
  if (size == 0) return 0;
  const std::string& path = file.write(data + 1, size - 1);
  if (data[0] & 1) {
    fuzz::Expect([&] { (void)pipeline::ReadStateFile(path); }, path);
  } else {
    // The case runner reports pointers; the command line adds the file name, so only the
    // JSON syntax errors (from ParseJsonFile) must name it here.
    fuzz::Expect(
        [&] {
          const nlohmann::json c = pipeline::ParseJsonFile(path);
          fuzz::Expect([&] { refcase::Run(reg, c); }, "");
        },
        path);
  }
  return 0;
}
