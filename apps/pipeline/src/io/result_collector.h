// The result-array collector fed with value events (value_events.h) rather than JSON text: how
// RunToArrays (imuconv/pipeline/pipeline.h) collects a run's arrays. Internal to
// imuconv_pipeline.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "imuconv/pipeline/result_arrays.h"

namespace imuconv::pipeline::detail {

class Collector;  // array_collector.h

class EventCollector {
 public:
  /// `what` names the document in messages, as CollectResultArrays' argument does.
  explicit EventCollector(std::string what);
  ~EventCollector();
  EventCollector(const EventCollector&) = delete;
  EventCollector& operator=(const EventCollector&) = delete;

  /// The next piece of the event stream, in order.
  void feed(std::string_view events);
  /// The arrays and sidecar (the same as CollectResultArrays gives for the document's text).
  ResultArrays finish();

 private:
  std::unique_ptr<Collector> c_;
  std::string carry_;  // a record cut at the end of a piece
};

}  // namespace imuconv::pipeline::detail
