// The result-array collector (internal to imuconv_pipeline): the output document's numbers as
// N-d arrays, read as the typed values a document is written with, keeping only the numbers
// (8 bytes each) and the sidecar's values. The rule is stated in imuconv/pipeline/result_arrays.h;
// the end of the collection (which keys fill a grid, the sidecar) is Collector::Finish in
// result_arrays.cpp.
//
// Two inputs call it: the writer's value records (value_events.h, for RunToArrays), where a
// vector or a matrix arrives whole with its shape (`reals`), and the document's text parsed
// (CollectResultArrays, result_arrays.cpp), where every array arrives element by element.
//
// How it streams: objects and arrays of objects are frames; a value's key is its frame's key
// and the member name. A vector or matrix given with its shape goes straight to its key. Any
// other array that is not an array of objects (a list of block labels; in the text, every
// vector and matrix) is built as a JSON value until it closes (built_array.h): it is then an
// N-d array when it is a rectangular array of numbers (the shape read off it), else a value for
// the sidecar.
// The indices of the enclosing arrays of objects are kept per value, so that the end can tell
// whether a key's values fill their grid (one N-d array) or not (one array per value, named by
// its pointer).
#pragma once

#include <algorithm>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "built_array.h"
#include "imuconv/pipeline/result_arrays.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "result_keys.h"

namespace imuconv::pipeline::detail {

class Collector {
 public:
  explicit Collector(std::string what) : what_(std::move(what)) {}

  // ---- the document's values, in order ----
  void null() {
    if (Built()) return built_.add(nullptr);
    EmitValue(Here("null"), nullptr);
  }
  void boolean(bool b) {
    if (Built()) return built_.add(b);
    EmitValue(Here("a boolean"), b);
  }
  void integer(std::int64_t i) {
    if (Built()) return built_.add(i);
    EmitNumbers(Here("a number"), nullptr, &i, 1, false);
  }
  void unsigned_integer(std::uint64_t u) {
    if (u <= static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      return integer(static_cast<std::int64_t>(u));
    if (Built()) return built_.add(u);  // beyond int64: a sidecar value, never an array
    EmitValue(Here("a number"), u);
  }
  void real(double v) {
    if (Built()) return built_.add(v);
    EmitNumbers(Here("a number"), &v, nullptr, 1, true);
  }
  /// A vector (`shape` {n}) or a matrix ({rows, cols}, row-major) of reals, whole: the doubles
  /// at `bytes` (native byte order, unaligned), as many as the shape's product. The same value
  /// as the nested arrays of real() it stands for.
  void reals(const char* bytes, const std::vector<std::size_t>& shape) {
    std::size_t n = 1;
    for (std::size_t e : shape) n *= e;
    if (n > 0 && !Built()) {  // nearly every vector and matrix of the output
      EmitNumbers(Here("an array"), bytes, nullptr, n, true, &shape);
      return;
    }
    // Inside an array being built, or empty (no numbers: a sidecar value): as the text has it.
    auto element = [&](std::size_t i) {
      double v;
      std::memcpy(&v, bytes + i * sizeof(double), sizeof v);
      real(v);
    };
    begin_array();
    if (shape.size() == 1) {
      for (std::size_t i = 0; i < shape[0]; ++i) element(i);
    } else {
      for (std::size_t r = 0; r < shape[0]; ++r) {
        begin_array();
        for (std::size_t c = 0; c < shape[1]; ++c) element(r * shape[1] + c);
        end_array();
      }
    }
    end_array();
  }
  void string(std::string_view s) {
    if (Built()) return built_.add(std::string(s));
    if (!frames_.empty() && frames_.back().task && !frames_.back().named) {
      // A task's name (its first member, checked in key()) names its frame.
      Frame& task = frames_.back();
      task.named = true;
      task.key = task.pointer = "tasks/" + Escape(std::string(s));
      task.key_id = FrameKeyId(task.key);
      task.member =
          &Slot(task.key_id, task.member->name, 0);  // "name", now under the task's own key
      if (!task_names_.emplace(s).second)
        Fail(task.pointer, "a second task named '" + Printable(std::string(s)) + "'");
    }
    // Most strings repeat their key's first value (a convention, a chart, per interval): such
    // a one is recorded without making a JSON value of it to compare.
    const Destination d = Here("a string");
    ValueKey& k = ValueKeyOf(d);
    Record(k, d);
    if (k.count == 1 || !k.first.is_string() || k.first.get_ref<const std::string&>() != s)
      k.Keep(std::string(s));
  }
  void begin_object() {
    CheckDepth();
    if (built_.building()) return built_.open(ojson::object());
    if (pending_array_) StartArrayOfObjects();
    if (frames_.empty()) {
      if (done_) Fail("", "text after the document");
      frames_.push_back(Frame{});
      frames_.back().key_id = FrameKeyId(frames_.back().key);
      return;
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
  }
  void key(std::string_view name) {
    if (built_.building()) return built_.key(name);
    const std::string k(name);
    Frame& f = frames_.back();
    if (f.task && !f.named && k != "name")
      Fail(f.pointer,
           "expected the task's \"name\" as its first member, found \"" + Printable(k) + "\"");
    f.member = &Slot(f.key_id, k, f.count);
    ++f.count;
  }
  void end_object() {
    if (built_.building()) return CloseBuilt();
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
  }
  void begin_array() {
    CheckDepth();
    if (built_.building()) return built_.open(ojson::array());
    if (pending_array_) {  // an array's first element is an array: the outer one is built
      StartBuilding();
      return built_.open(ojson::array());
    }
    array_dest_ = Here("an array");
    pending_array_ = true;  // an array of objects or a value: its first element tells
  }
  void end_array() {
    if (built_.building()) return CloseBuilt();
    if (pending_array_) {
      pending_array_ = false;
      EmitValue(array_dest_, ojson::array());
      return;
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
  }
  /// The text could not be parsed (CollectResultArrays).
  [[noreturn]] void not_json(std::size_t position, const std::string& why) const {
    Fail("", "not a JSON document (byte " + std::to_string(position) + "): " + why);
  }
  [[noreturn]] void refuse(const std::string& why) const { Fail("", why); }

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
    const std::size_t depth = frames_.size() + built_.depth() + (pending_array_ ? 1 : 0);
    if (depth >= kMaxDepth)
      Fail(frames_.empty() ? std::string() : frames_.back().pointer,
           "nested deeper than " + std::to_string(kMaxDepth) + " levels");
  }

  /// Whether the current value goes into the array being built (it is inside one, or is the
  /// first element, not an object, of an array just opened).
  bool Built() {
    if (built_.building()) return true;
    if (!pending_array_) return false;
    StartBuilding();
    return true;
  }
  void StartBuilding() {
    pending_array_ = false;
    built_.start();
  }
  void CloseBuilt() {
    if (built_.close()) FlushBuilt();
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
  /// The destination of a value that is not in an array being built: the current object's member.
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
  /// asked for only while that frame is still the innermost one (an array being built opens no
  /// frame).
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

  /// The array just built (built_array.h): an N-d array when it is a rectangular array of
  /// numbers, else a value for the sidecar.
  void FlushBuilt() {
    BuiltArray::Numbers& n = numbers_;
    if (!built_.rectangular(n)) return EmitValue(array_dest_, built_.take());
    if (!n.real)
      return EmitNumbers(array_dest_, nullptr, n.integers.data(), n.integers.size(), false,
                         &n.shape);
    if (n.mixed) {  // reals and integers, in the order of the document: each integer as a real
      n.reals.clear();
      built_.each_number([&](const ojson& v) {
        n.reals.push_back(v.is_number_float() ? v.get<double>()
                                              : ExactDouble(v.get<std::int64_t>(), array_dest_));
      });
    }
    EmitNumbers(array_dest_, n.reals.data(), nullptr, n.reals.size(), true, &n.shape);
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

  /// The n numbers of a value at `d`, of `shape` (none: a number alone): the doubles at
  /// `reals` (native byte order, possibly unaligned: a value record's own bytes), or `integers`
  /// when !real.
  void EmitNumbers(const Destination& d, const void* reals, const std::int64_t* integers,
                   std::size_t n, bool real, const std::vector<std::size_t>* shape = nullptr) {
    if (shape == nullptr && levels_.empty()) {  // a number alone, in no array of objects
      double v = 0.0;
      if (real) std::memcpy(&v, reals, sizeof v);
      EmitValue(d, real ? ojson(v) : ojson(integers[0]));
      return;
    }
    if (d.slot == nullptr || d.slot->numeric < 0) {
      const auto [it, added] = numeric_ids_.emplace(KeyOf(d), numeric_.size());
      if (added) {
        numeric_.emplace_back();
        numeric_.back().key = KeyOf(d);
        numeric_.back().type = real ? NdArray::Type::kFloat64 : NdArray::Type::kInt64;
      }
      if (d.slot != nullptr) d.slot->numeric = static_cast<int>(it->second);
      return AddNumbers(numeric_[it->second], d, reals, integers, n, real, shape);
    }
    AddNumbers(numeric_[static_cast<std::size_t>(d.slot->numeric)], d, reals, integers, n, real,
               shape);
  }
  void AddNumbers(NumericKey& k, const Destination& d, const void* reals,
                  const std::int64_t* integers, std::size_t n, bool real,
                  const std::vector<std::size_t>* shape) {
    Record(k, d);
    k.Append(shape ? *shape : no_shape_, reals, integers, n, real,
             [&](std::int64_t i) { return ExactDouble(i, d); });
  }

  void EmitValue(const Destination& d, ojson v) {
    ValueKey& k = ValueKeyOf(d);
    Record(k, d);
    k.Keep(std::move(v));
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
  Destination array_dest_;
  BuiltArray built_;                   ///< an array that is not of objects, while it is read
  BuiltArray::Numbers numbers_;        ///< FlushBuilt's (reused)
  std::vector<std::size_t> no_shape_;  ///< a number's shape (none)
  std::deque<FrameKey> frame_keys_;    ///< every frame key met, and its members
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
