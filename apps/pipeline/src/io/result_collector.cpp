// The result-array collector fed with the writer's value events (result_collector.h): pieces
// of the event stream are replayed into the same collector the text is parsed into, a record
// cut at a piece's end carried to the next.
#include "result_collector.h"

#include <stdexcept>

#include "array_collector.h"
#include "value_events.h"

namespace imuconv::pipeline::detail {

EventCollector::EventCollector(std::string what)
    : c_(std::make_unique<Collector>(std::move(what))) {}
EventCollector::~EventCollector() = default;

void EventCollector::feed(std::string_view events) {
  if (carry_.empty()) {
    const std::size_t used = ReplayEvents(events, *c_);
    carry_.assign(events.substr(used));
    return;
  }
  carry_.append(events.data(), events.size());
  const std::size_t used = ReplayEvents(carry_, *c_);
  carry_.erase(0, used);
}

ResultArrays EventCollector::finish() {
  if (!carry_.empty()) throw std::logic_error("value events: a record was cut short");
  return c_->Finish();
}

}  // namespace imuconv::pipeline::detail
