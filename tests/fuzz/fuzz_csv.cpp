// libFuzzer target: the IMU and ground-truth CSV readers. The first byte picks the reader and
// the generic CSV format (delimiter, header rows, column map by index or by name, time unit);
// the rest is the file.
#include "fuzz_support.h"
#include "imuconv/pipeline/imu_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace imuconv::pipeline;
  static imuconv::fuzz::InputFile file("data.csv");
  if (size == 0) return 0;
  const std::uint8_t mode = data[0];
  const std::string& path = file.write(data + 1, size - 1);
  imuconv::fuzz::Expect(
      [&] {
        switch (mode % 4) {
          case 0:
            ReadEurocImu(path);
            break;
          case 1: {
            TimeOrigin origin;
            origin.unit = TimeUnit::ns;
            ReadEurocGroundTruth(path, origin);
            break;
          }
          default: {
            CsvFormat f;
            f.delimiter = (mode & 4) ? ';' : ',';
            f.whitespace_delimited = (mode & 8) != 0;
            f.header_rows = (mode >> 4) & 1;
            f.comment = (mode & 32) ? "#" : "";
            f.time_unit = (mode & 64) ? TimeUnit::ns : TimeUnit::s;
            if (mode & 128) {
              // By name when there is a header, else indices past any short row.
              if (f.header_rows > 0)
                f.columns = {std::string("t"),  std::string("wx"), std::string("wy"),
                             std::string("wz"), std::string("ax"), std::string("ay"),
                             std::string("az")};
              else
                f.columns = {0, 2, 4, 6, 8, 10, 12};
            } else if (mode % 4 == 3) {
              f.columns = {6, 5, 4, 3, 2, 1, 9};  // one index past a 7-column header
            }
            ReadCsvImu(path, f);
            break;
          }
        }
      },
      path);
  return 0;
}
