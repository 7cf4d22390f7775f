#include "imuconv/pipeline/file_digest.h"

#include <cstdio>
#include <fstream>
#include <vector>

#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/input_registry.h"

namespace imuconv::pipeline {

std::string Fnv1a64::hex() const {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(value_));
  return buf;
}

FileDigest DigestFile(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw ReadError(file, 0, "cannot be opened to record its hash in the shard");
  RegisterInputPath(file);  // an input like any other: no output may replace it (input_registry.h)
  FileDigest d;
  std::vector<char> buf(std::size_t{1} << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const auto got = static_cast<std::size_t>(in.gcount());
    d.hash.add(buf.data(), got);
    d.bytes += got;
  }
  if (in.bad())
    throw ReadError(file, 0, "could not be read to the end to record its hash in the shard");
  return d;
}

}  // namespace imuconv::pipeline
