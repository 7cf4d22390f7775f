// The state form {"p", "q_wxyz", "v", "bg", "ba"} and the bias form {"bg", "ba"}: the
// streaming writers (the reader and the json value form are declared in json_io.h; all are
// implemented in state.cpp, side by side).
#pragma once

#include "imuconv/pipeline/json_io.h"
#include "imuconv/pipeline/json_writer.h"

namespace imuconv::pipeline {

void WriteState(JsonWriter& w, const ImuState& x);
void WriteBias(JsonWriter& w, const Vec3& bg, const Vec3& ba);

}  // namespace imuconv::pipeline
