// Where an output document's text goes while it is written (RunToText, the output stream).
#pragma once

#include <functional>
#include <string_view>

namespace imuconv::pipeline {

/// Receives the output document's text in order, in pieces.
using TextSink = std::function<void(std::string_view)>;

}  // namespace imuconv::pipeline
