// The output document's numbers as N-d arrays: the end of the collection (Collector::Finish:
// which keys fill their grid, the sidecar) and the two ways in, the document's text
// (CollectResultArrays, parsed here) and the writer's value events (EventCollector,
// result_collector.cpp). The collector itself is array_collector.h; the rule is stated in
// imuconv/pipeline/result_arrays.h.
#include "imuconv/pipeline/result_arrays.h"

#include <cstdio>
#include <istream>
#include <nlohmann/json.hpp>
#include <unordered_set>

#include "array_collector.h"
#include "file_streambuf.h"

namespace imuconv::pipeline {
namespace detail {

ResultArrays Collector::Finish() {
  if (!done_) Fail("", "the document is incomplete");
  ResultArrays r;
  std::unordered_set<std::string> names{kSidecarKey};
  auto add = [&](std::string name, NdArray a) {
    if (!names.insert(name).second)
      Fail(name, name == kSidecarKey ? "an array would take the sidecar's name"
                                     : "two arrays would have this name");
    r.arrays.emplace_back(std::move(name), std::move(a));
  };
  ojson stacked = ojson::object(), values = ojson::object();
  for (NumericKey& k : numeric_) {
    std::vector<std::size_t> dims;
    if (k.shapes.size() == 1 && FillsGrid(k, dims)) {
      NdArray a;
      a.type = k.type;
      a.shape = dims;
      a.shape.insert(a.shape.end(), k.shapes[0].begin(), k.shapes[0].end());
      a.data = std::move(k.data);
      a.integers = std::move(k.integers);
      if (!k.levels.empty()) {
        ojson over = ojson::array();
        for (int id : k.levels) over.push_back(aoos_[static_cast<std::size_t>(id)].key);
        stacked[k.key] = std::move(over);
      }
      add(k.key, std::move(a));
    } else {
      for (std::size_t n = 0; n < k.count; ++n) {
        NdArray a;
        a.type = k.type;
        a.shape = k.shapes[k.shape_of[n]];
        std::size_t size = 1;
        for (std::size_t e : a.shape) size *= e;
        const auto from = static_cast<std::ptrdiff_t>(k.offset[n]),
                   to = from + static_cast<std::ptrdiff_t>(size);
        if (k.type == NdArray::Type::kFloat64)
          a.data.assign(k.data.begin() + from, k.data.begin() + to);
        else
          a.integers.assign(k.integers.begin() + from, k.integers.begin() + to);
        add(PointerOf(k, n), std::move(a));
      }
    }
    k = NumericKey{};  // its numbers now live in r
  }
  std::unordered_set<std::string> value_names;
  auto put = [&](const std::string& name, const ojson& v) {
    if (!value_names.insert(name).second) Fail(name, "two sidecar values would have this name");
    values[name] = v;
  };
  for (const ValueKey& k : values_) {
    std::vector<std::size_t> dims;
    if (k.other.empty() && FillsGrid(k, dims)) {
      put(k.key, k.first);
      continue;
    }
    std::size_t next_other = 0;
    for (std::size_t n = 0; n < k.count; ++n) {
      const bool differs = next_other < k.other.size() && k.other[next_other].first == n;
      put(PointerOf(k, n), differs ? k.other[next_other++].second : k.first);
    }
  }
  ojson sidecar = ojson::object();
  sidecar["format"] = "imuconv-npz";
  sidecar["format_version"] = 1;
  sidecar["values"] = std::move(values);
  sidecar["stacked_over"] = std::move(stacked);
  r.sidecar = sidecar.dump(-1, ' ', true);
  return r;
}

}  // namespace detail

namespace {

/// The parsed text's values into the collector (nlohmann::json's SAX interface), one by one:
/// every array element by element, its shape read off it when it closes.
struct TextValues {
  detail::Collector& c;
  bool null() { return c.null(), true; }
  bool boolean(bool b) { return c.boolean(b), true; }
  bool number_integer(std::int64_t i) { return c.integer(i), true; }
  bool number_unsigned(std::uint64_t u) { return c.unsigned_integer(u), true; }
  bool number_float(double v, const std::string&) { return c.real(v), true; }
  bool string(std::string& s) { return c.string(s), true; }
  bool binary(nlohmann::json::binary_t&) { c.refuse("binary values are not JSON text"); }
  bool start_object(std::size_t) { return c.begin_object(), true; }
  bool key(std::string& k) { return c.key(k), true; }
  bool end_object() { return c.end_object(), true; }
  bool start_array(std::size_t) { return c.begin_array(), true; }
  bool end_array() { return c.end_array(), true; }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::json::exception& e) {
    c.not_json(position, e.what());
  }
};

}  // namespace

ResultArrays CollectResultArrays(std::FILE* text, const std::string& what) {
  detail::FileReader reader(text);
  std::istream in(&reader);
  detail::Collector c(what);
  TextValues values{c};
  nlohmann::json::sax_parse(in, &values);
  if (std::ferror(text)) throw Error(what + ": reading the text back failed");
  return c.Finish();
}

ResultArrays CollectResultArrays(std::string_view text, const std::string& what) {
  detail::Collector c(what);
  TextValues values{c};
  nlohmann::json::sax_parse(text.begin(), text.end(), &values);
  return c.Finish();
}

}  // namespace imuconv::pipeline
