// The output document's stream (internal to imuconv_pipeline).
//
// Tasks write with a JsonWriter into text(); the text goes to the caller's sink in pieces
// (about 1 MiB, or one interval's text), so that a large document is never held in memory.
// Independent intervals are computed and formatted on a thread pool (write_elements): each
// element's text depends on its index only and goes to the sink in index order, so the
// document is the same byte for byte for any thread count. With JsonWriter::Form::kEvents the
// pieces are value events instead of text (the NPZ output collects its arrays from them).
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/text_sink.h"
#include "imuconv/registry.h"
#include "thread_pool.h"

namespace imuconv::pipeline {

/// The sink could not take the output (e.g. a full disk): reported as it is, not as a task's.
class SinkFailure : public Error {
 public:
  using Error::Error;
};

class Output {
 public:
  Output(const TextSink& sink, unsigned threads, JsonWriter::Form form = JsonWriter::Form::kText)
      : sink_(sink), pool_(threads), form_(form) {}

  /// What the writers write: text, or value events.
  JsonWriter::Form form() const noexcept { return form_; }

  /// Where the document is written (JsonWriter's string).
  std::string& text() { return buf_; }
  /// Hands the text to the sink: all of it, or once it is about 1 MiB.
  void flush(bool all);

  /// Writes n elements of the open array of `w`, element k by write_one(writer, k) (which
  /// may compute it first): run on the pool, each into its own string by its own writer, and
  /// handed to the sink in order as soon as it is there (at most window() elements ahead).
  /// The text is the same as writing them one after the other into `w`. consumed(k) runs on
  /// the calling thread, in order, once element k is in the sink; what write_one(., k) left
  /// in a slot of index k % window() is still there for it.
  template <typename F, typename G>
  void write_elements(JsonWriter& w, std::size_t n, const F& write_one, const G& consumed) {
    const int depth = w.content_depth();
    const std::string base = w.container_pointer();
    const std::string first_sep = w.element_separator(true), sep = w.element_separator(false);
    const std::size_t slots_n = window();
    std::vector<std::string> slots(std::min(slots_n, n));
    pool_.ordered_for(
        n, slots_n,
        [&](std::size_t k) {
          std::string& text = slots[k % slots_n];
          text = k == 0 ? first_sep : sep;
          JsonWriter cw(text, depth, base + "/" + std::to_string(k), JsonWriter::NonFinite::Throw,
                        form_);
          write_one(cw, k);
        },
        [&](std::size_t k) {
          if (k == 0) flush(true);  // what comes before the elements
          sink(slots[k % slots_n]);
          slots[k % slots_n] = std::string();  // a long element's text is not held on to
          ++records_;
          consumed(k);
        });
    w.skip_elements(n);
  }
  /// Elements in flight at most in write_elements.
  std::size_t window() const { return 16 * static_cast<std::size_t>(pool_.size()); }

  /// One interval result was written outside write_elements (RunOptions::Stats::records).
  void count_record() { ++records_; }
  std::size_t records() const { return records_; }

 private:
  void sink(std::string_view text);

  const TextSink& sink_;
  ThreadPool pool_;
  JsonWriter::Form form_;
  std::string buf_;  // output not yet handed to the sink
  std::size_t records_ = 0;
};

}  // namespace imuconv::pipeline
