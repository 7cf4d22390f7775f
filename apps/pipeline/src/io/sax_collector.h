// The result-array collector (internal to imuconv_pipeline): the output document's numbers as
// N-d arrays, read as a stream of JSON events (nlohmann::json's SAX interface), keeping only
// the numbers (8 bytes each) and the sidecar's values. The rule is stated in
// imuconv/pipeline/result_arrays.h; the end of the collection (which keys fill a grid, the
// sidecar) is Collector::Finish in result_arrays.cpp.
//
// How it streams: objects and arrays of objects are frames; a value's key is its frame's key
// and the member name. An array that is not an array of objects (a vector, a matrix, a list of
// block labels) is buffered as events until it closes, then replayed: into an N-d array when
// it is a rectangular array of numbers, else into a JSON value for the sidecar. The indices of
// the enclosing arrays of objects are kept per value, so that the end can tell whether a key's
// values fill their grid (one N-d array) or not (one array per value, named by its pointer).
#pragma once

#include <algorithm>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "result_keys.h"
#include "value_buffer.h"

namespace imuconv::pipeline::detail {

class Collector {
 public:
  explicit Collector(std::string what) : what_(std::move(what)) {}

  // ---- nlohmann::json's SAX interface ----
  bool null() {
    if (Buffered()) return Add(ValueBuffer::kNull);
    EmitValue(Here("null"), nullptr);
    return true;
  }
  bool boolean(bool b) {
    if (Buffered()) return Add(b ? ValueBuffer::kTrue : ValueBuffer::kFalse);
    EmitValue(Here("a boolean"), b);
    return true;
  }
  bool number_integer(std::int64_t i) {
    if (Buffered()) {
      buf_.ints.push_back(i);
      return Add(ValueBuffer::kInt);
    }
    EmitNumbers(Here("a number"), {}, {}, {i}, false);
    return true;
  }
  bool number_unsigned(std::uint64_t u) {
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      return number_integer(static_cast<std::int64_t>(u));
    if (Buffered()) {
      buf_.big.push_back(u);
      return Add(ValueBuffer::kBigUInt);
    }
    EmitValue(Here("a number"), u);
    return true;
  }
  bool number_float(double v, const std::string&) {
    if (Buffered()) {
      buf_.floats.push_back(v);
      return Add(ValueBuffer::kFloat);
    }
    EmitNumbers(Here("a number"), {}, {v}, {}, true);
    return true;
  }
  /// `n` doubles (native byte order, unaligned) read as n number_float events, all at once: a
  /// one-line array of the writer's value events (value_events.h), always buffered.
  void number_row(const char* bytes, std::size_t n) {
    if (n == 0) return;
    Buffered();  // opens the buffer when this is the first element of the array
    buf_.events.insert(buf_.events.end(), n, ValueBuffer::kFloat);
    const std::size_t at = buf_.floats.size();
    buf_.floats.resize(at + n);
    std::memcpy(buf_.floats.data() + at, bytes, n * sizeof(double));
  }
  bool string(std::string& s) {
    if (Buffered()) {
      buf_.strings.push_back(s);
      return Add(ValueBuffer::kString);
    }
    if (!frames_.empty() && frames_.back().task && !frames_.back().named) {
      // A task's name (its first member, checked in key()) names its frame.
      Frame& task = frames_.back();
      task.named = true;
      task.key = task.pointer = "tasks/" + Escape(s);
      task.key_id = FrameKeyId(task.key);
      task.member =
          &Slot(task.key_id, task.member->name, 0);  // "name", now under the task's own key
      if (!task_names_.insert(s).second)
        Fail(task.pointer, "a second task named '" + Printable(s) + "'");
    }
    EmitValue(Here("a string"), s);
    return true;
  }
  bool binary(nlohmann::json::binary_t&) { Fail("", "binary values are not JSON text"); }
  bool start_object(std::size_t) {
    CheckDepth();
    if (buffer_depth_ > 0) {
      ++buffer_depth_;
      return Add(ValueBuffer::kBeginObject);
    }
    if (pending_array_) StartArrayOfObjects();
    if (frames_.empty()) {
      if (done_) Fail("", "text after the document");
      frames_.push_back(Frame{});
      frames_.back().key_id = FrameKeyId(frames_.back().key);
      return true;
    }
    Frame& f = frames_.back();
    Frame child;
    if (f.aoo) {
      if (f.tasks) {
        child.task = true;
        child.key = child.pointer = "tasks/" + std::to_string(f.count);  // until its name is read
        child.key_id = FrameKeyId(child.key);
      } else {
        index_.push_back(f.count);
        levels_.push_back(f.aoo_id);
        child.key = f.key;
        child.key_id = f.key_id;
        child.pointer = f.pointer + "/" + std::to_string(f.count);
        child.element = true;
      }
    } else {
      const Destination d = Here("an object");
      child.key = KeyOf(d);
      child.key_id = ChildKeyId(*d.slot);
      child.pointer = PointerOf(d);
    }
    frames_.push_back(std::move(child));
    return true;
  }
  bool key(std::string& k) {
    if (buffer_depth_ > 0) {
      buf_.strings.push_back(k);
      return Add(ValueBuffer::kKey);
    }
    Frame& f = frames_.back();
    if (f.task && !f.named && k != "name")
      Fail(f.pointer,
           "expected the task's \"name\" as its first member, found \"" + Printable(k) + "\"");
    f.member = &Slot(f.key_id, k, f.count);
    ++f.count;
    return true;
  }
  bool end_object() {
    if (buffer_depth_ > 0) {
      --buffer_depth_;
      return Add(ValueBuffer::kEndObject);
    }
    Frame f = std::move(frames_.back());
    frames_.pop_back();
    if (f.task && !f.named) Fail(f.pointer, "a task without a \"name\"");
    // An empty object has no values to carry it: the sidecar records it.
    if (f.count == 0 && !frames_.empty()) EmitValue({nullptr, f.key, f.pointer}, ojson::object());
    if (f.element) {
      index_.pop_back();
      levels_.pop_back();
    }
    if (frames_.empty())
      done_ = true;
    else if (frames_.back().aoo)
      ++frames_.back().count;
    return true;
  }
  bool start_array(std::size_t) {
    CheckDepth();
    if (buffer_depth_ > 0) {
      ++buffer_depth_;
      return Add(ValueBuffer::kBeginArray);
    }
    if (pending_array_) {
      StartBuffer();
      ++buffer_depth_;
      return Add(ValueBuffer::kBeginArray);
    }
    array_dest_ = Here("an array");
    pending_array_ = true;  // an array of objects or a value: its first element tells
    return true;
  }
  bool end_array() {
    if (buffer_depth_ > 0) {
      Add(ValueBuffer::kEndArray);
      if (--buffer_depth_ == 0) FlushBuffer();
      return true;
    }
    if (pending_array_) {
      pending_array_ = false;
      EmitValue(array_dest_, ojson::array());
      return true;
    }
    const Frame a = std::move(frames_.back());
    frames_.pop_back();
    if (!a.tasks) {
      ArrayOfObjects& info = aoos_[static_cast<std::size_t>(a.aoo_id)];
      if (info.instances++ == 0)
        info.length = a.count;
      else if (info.length != a.count)
        info.ragged = true;
    }
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::json::exception& e) {
    Fail("", "not a JSON document (byte " + std::to_string(position) + "): " + e.what());
  }

  ResultArrays Finish();

 private:
  using Frame = detail::Frame;
  using ArrayOfObjects = detail::ArrayOfObjects;
  using Occurrences = detail::Occurrences;
  using NumericKey = detail::NumericKey;
  using ValueKey = detail::ValueKey;

  [[noreturn]] void Fail(const std::string& pointer, const std::string& message) const {
    throw Error(what_ + ": /" + Printable(pointer) + ": " + message);
  }

  /// Nesting is bounded (an output document is a few levels deep): JSON values are copied and
  /// written recursively, and a hostile text must not exhaust the stack.
  void CheckDepth() const {
    const std::size_t depth =
        frames_.size() + static_cast<std::size_t>(buffer_depth_) + (pending_array_ ? 1 : 0);
    if (depth >= kMaxDepth)
      Fail(frames_.empty() ? std::string() : frames_.back().pointer,
           "nested deeper than " + std::to_string(kMaxDepth) + " levels");
  }

  bool Add(ValueBuffer::Event e) {
    buf_.events.push_back(e);
    return true;
  }
  /// Whether the current value goes into the buffer (it is inside, or is the first element
  /// of, an array that is not an array of objects).
  bool Buffered() {
    if (buffer_depth_ > 0) return true;
    if (!pending_array_) return false;
    StartBuffer();
    return true;
  }
  void StartBuffer() {
    pending_array_ = false;
    buf_.clear();
    buf_.events.push_back(ValueBuffer::kBeginArray);
    buffer_depth_ = 1;
  }
  void StartArrayOfObjects() {
    pending_array_ = false;
    Frame a;
    a.aoo = true;
    a.key = KeyOf(array_dest_);
    a.pointer = PointerOf(array_dest_);
    a.key_id = array_dest_.slot ? ChildKeyId(*array_dest_.slot) : FrameKeyId(a.key);
    a.tasks = frames_.size() == 1 && a.pointer == "tasks";
    if (!a.tasks) {
      const int parent = levels_.empty() ? -1 : levels_.back();
      const auto [it, added] = aoo_ids_.emplace(a.key, static_cast<int>(aoos_.size()));
      if (added)
        aoos_.push_back({a.key, parent});
      else if (aoos_[static_cast<std::size_t>(it->second)].parent != parent)
        Fail(a.pointer,
             "an array of objects nested differently from an earlier one of the same key");
      a.aoo_id = it->second;
    }
    frames_.push_back(std::move(a));
  }
  /// The destination of a value that is not in a buffer: the current object's member.
  Destination Here(const char* found) const {
    if (frames_.empty()) Fail("", std::string("expected an object at the top, found ") + found);
    const Frame& f = frames_.back();
    if (f.aoo)
      Fail(f.pointer + "/" + std::to_string(f.count),
           std::string("expected an object (the array's first element is one), found ") + found);
    if (f.task && !f.named)
      Fail(f.pointer + "/name", std::string("expected the task's name (a string), found ") + found);
    if (f.member == nullptr)
      throw std::logic_error("result collector: a value in an object before its member name");
    return {f.member, {}, {}};
  }
  /// A destination's key and pointer. A slot's pointer is the innermost frame's member: it is
  /// asked for only while that frame is still the innermost one (a buffered array opens no frame).
  const std::string& KeyOf(const Destination& d) const { return d.slot ? d.slot->key : d.key; }
  std::string PointerOf(const Destination& d) const {
    return d.slot ? Join(frames_.back().pointer, d.slot->escaped) : d.pointer;
  }

  /// The entry of a frame key in frame_keys_, added when new.
  int FrameKeyId(const std::string& key) {
    const auto [it, added] = frame_key_ids_.emplace(key, static_cast<int>(frame_keys_.size()));
    if (added) frame_keys_.push_back(FrameKey{key, {}});
    return it->second;
  }
  int ChildKeyId(MemberSlot& slot) {
    if (slot.child_key < 0) slot.child_key = FrameKeyId(slot.key);
    return slot.child_key;
  }
  /// The member `name` under the frame key `key_id`: looked for first where the previous object
  /// of this key had its member number `position`, then among all its members; added when new.
  MemberSlot& Slot(int key_id, const std::string& name, std::size_t position) {
    FrameKey& fk = frame_keys_[static_cast<std::size_t>(key_id)];
    if (position < fk.members.size() && fk.members[position].name == name)
      return fk.members[position];
    for (MemberSlot& m : fk.members)
      if (m.name == name) return m;
    MemberSlot m;
    m.name = name;
    m.escaped = Escape(name);
    m.key = Join(fk.key, m.escaped);
    fk.members.push_back(std::move(m));
    return fk.members.back();
  }

  void FlushBuffer() {
    std::vector<std::size_t>& shape =
        shape_;  // reused: one array per vector or matrix of the output
    if (!buf_.Rectangular(shape)) {
      EmitBufferedValue(array_dest_);
      return;
    }
    if (buf_.floats.empty()) {
      EmitNumbers(array_dest_, shape, {}, buf_.ints, false);
      return;
    }
    if (buf_.ints.empty()) {  // reals only (nearly every array): the buffer's own
      EmitNumbers(array_dest_, shape, buf_.floats, {}, true);
      return;
    }
    // Reals, and integers too when there are any (in the order of the text).
    std::vector<double> v;
    v.reserve(buf_.floats.size() + buf_.ints.size());
    std::size_t i_int = 0, i_float = 0;
    for (ValueBuffer::Event e : buf_.events) {
      if (e == ValueBuffer::kFloat)
        v.push_back(buf_.floats[i_float++]);
      else if (e == ValueBuffer::kInt)
        v.push_back(ExactDouble(buf_.ints[i_int++], array_dest_));
    }
    EmitNumbers(array_dest_, shape, std::move(v), {}, true);
  }

  double ExactDouble(std::int64_t i, const Destination& d) const {
    if (i > kExactInDouble || i < -kExactInDouble)
      Fail(PointerOf(d), "mixes integers and reals, and the integer " + std::to_string(i) +
                             " is not exact as a double");
    return static_cast<double>(i);
  }

  /// Records one more value of the key `o` at the current indices (they must come after the
  /// last value's: two at the same indices are a duplicate key).
  void Record(Occurrences& o, const Destination& d) {
    if (o.count == 0) {
      o.levels = levels_;
    } else {
      if (o.levels != levels_)
        Fail(PointerOf(d),
             "reached through other arrays of objects than earlier values of its key");
      const std::size_t n = levels_.size();
      if (!std::lexicographical_compare(o.indices.end() - static_cast<std::ptrdiff_t>(n),
                                        o.indices.end(), index_.begin(), index_.end()))
        Fail(PointerOf(d), "a duplicate key");
    }
    o.indices.insert(o.indices.end(), index_.begin(), index_.end());
    ++o.count;
  }

  void EmitNumbers(const Destination& d, const std::vector<std::size_t>& shape,
                   const std::vector<double>& reals, const std::vector<std::int64_t>& integers,
                   bool real) {
    if (shape.empty() && levels_.empty()) {  // a number alone, in no array of objects
      EmitValue(d, real ? ojson(reals[0]) : ojson(integers[0]));
      return;
    }
    if (d.slot == nullptr || d.slot->numeric < 0) {
      const auto [it, added] = numeric_ids_.emplace(KeyOf(d), numeric_.size());
      if (added) {
        numeric_.emplace_back();
        numeric_.back().key = KeyOf(d);
        numeric_.back().type = real ? NdArray::Type::kFloat64 : NdArray::Type::kInt64;
      }
      if (d.slot == nullptr)
        return AddNumbers(numeric_[it->second], d, shape, reals, integers, real);
      d.slot->numeric = static_cast<int>(it->second);
    }
    AddNumbers(numeric_[static_cast<std::size_t>(d.slot->numeric)], d, shape, reals, integers,
               real);
  }
  void AddNumbers(NumericKey& k, const Destination& d, const std::vector<std::size_t>& shape,
                  const std::vector<double>& reals, const std::vector<std::int64_t>& integers,
                  bool real) {
    Record(k, d);
    k.Append(shape, reals, integers, real, [&](std::int64_t i) { return ExactDouble(i, d); });
  }

  void EmitValue(const Destination& d, ojson v) {
    ValueKey& k = ValueKeyOf(d);
    Record(k, d);
    k.Keep(std::move(v));
  }
  /// EmitValue of the buffered array (not a rectangular array of numbers: a list of labels, say).
  /// The same list recurs once per element of an array of objects: when its events are those of
  /// the key's first value, so is its JSON value (equal numbers compared as JSON compares them),
  /// and it is neither built nor compared. Otherwise it is built and compared as EmitValue does.
  void EmitBufferedValue(const Destination& d) {
    ValueKey& k = ValueKeyOf(d);
    if (k.count > 0 && k.first_from_buffer && buf_.SameEvents(k.first_buffer)) {
      Record(k, d);
      return;
    }
    ojson v = buf_.ToJson();
    Record(k, d);
    if (k.Keep(std::move(v))) {
      k.first_buffer = buf_;
      k.first_from_buffer = true;
    }
  }
  ValueKey& ValueKeyOf(const Destination& d) {
    std::size_t id;
    if (d.slot != nullptr && d.slot->value >= 0) {
      id = static_cast<std::size_t>(d.slot->value);
    } else {
      const auto [it, added] = value_ids_.emplace(KeyOf(d), values_.size());
      if (added) {
        values_.emplace_back();
        values_.back().key = KeyOf(d);
      }
      id = it->second;
      if (d.slot != nullptr) d.slot->value = static_cast<int>(id);
    }
    return values_[id];
  }

  /// Whether the values of `o` fill the grid of its arrays of objects exactly; their lengths.
  bool FillsGrid(const Occurrences& o, std::vector<std::size_t>& dims) const {
    std::size_t cells = 1;
    for (int id : o.levels) {
      const ArrayOfObjects& a = aoos_[static_cast<std::size_t>(id)];
      // Present once in every element of the enclosing array, with one length.
      if (a.ragged || a.instances != cells) return false;
      dims.push_back(a.length);
      cells *= a.length;
    }
    return o.count == cells;  // distinct, in order and within the grid (Record): every cell
  }

  /// The pointer of value `n` of `o`: its key with the indices put back.
  std::string PointerOf(const Occurrences& o, std::size_t n) const {
    std::string p = o.key;
    const std::size_t depth = o.levels.size();
    for (std::size_t j = depth; j-- > 0;) {
      const std::size_t at = aoos_[static_cast<std::size_t>(o.levels[j])].key.size();
      p.insert(at, "/" + std::to_string(o.indices[n * depth + j]));
    }
    return p;
  }

  std::string what_;
  std::vector<Frame> frames_;
  bool done_ = false;
  bool pending_array_ = false;
  int buffer_depth_ = 0;
  Destination array_dest_;
  ValueBuffer buf_;
  std::vector<std::size_t> shape_;   ///< FlushBuffer's
  std::deque<FrameKey> frame_keys_;  ///< every frame key met, and its members
  std::unordered_map<std::string, int> frame_key_ids_;
  std::vector<std::uint32_t> index_;  ///< indices of the enclosing arrays of objects
  std::vector<int> levels_;           ///< and their entries in aoos_
  std::vector<ArrayOfObjects> aoos_;
  std::unordered_map<std::string, int> aoo_ids_;
  std::unordered_set<std::string> task_names_;
  std::vector<NumericKey> numeric_;
  std::unordered_map<std::string, std::size_t> numeric_ids_;
  std::vector<ValueKey> values_;
  std::unordered_map<std::string, std::size_t> value_ids_;
};

}  // namespace imuconv::pipeline::detail
