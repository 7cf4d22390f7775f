// PrettyJson (json_io.h); the forms themselves are in forms/.
#include "imuconv/pipeline/json_io.h"

#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

std::string PrettyJson(const json& j) {
  std::string out;
  JsonWriter w(out, 0, {}, JsonWriter::NonFinite::Null);
  w.value(j);
  out += "\n";
  return out;
}

}  // namespace imuconv::pipeline
