// The reader of imuconv run --shard K/N's documents and their merge (shard_merge.h).
//
// A shard is the whole run's document with a first member "shard" (its index, the split, the
// inputs' sizes and hashes), only its block of tasks, and a last member "shard_fnv1a_64" (run.cpp,
// Execute). The pipeline's JsonWriter writes every task element with the same text whatever its
// index (the splicing its thread pool relies on), so the merge copies text: the head once, then
// each shard's elements in shard order, with the separators and closing brackets the writer
// itself gives for their place. Nothing is parsed but the small "shard" member (through the one
// JSON reader, ParseJsonText); the elements are streamed through a fixed buffer, one shard file
// open at a time, so memory does not grow with the shards' size.
//
// The last member is the FNV-1a 64 of the shard's bytes from the first up to the bracket
// closing "tasks" (the "shard" member, the head and every element). Every shard is read through
// once and its hash checked before anything is written (a byte removed or a number changed is
// refused, naming the file), and again while it is copied (a file that changed in between is
// refused; the caller's output, written atomically, is then not created).
#include "imuconv/pipeline/shard_merge.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "../io/input_file.h"
#include "imuconv/pipeline/errors.h"
#include "imuconv/pipeline/file_digest.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/printable.h"

namespace imuconv::pipeline {
namespace {

/// The fixed text between the pieces, as the pipeline's JsonWriter lays out a run's document
/// (apps/pipeline/src/run/run.cpp: the "shard" member, the head whose first key is
/// "imuconv_version", then "tasks").
struct ShardLayout {
  std::string shard_open;           ///< the shard document's text before the "shard" member's value
  std::string shard_close;          ///< after that value, up to the head's first value
  std::string whole_open;           ///< the whole document's text before the head's first value
  std::string tasks_open;           ///< the end of the head: the "tasks" key and its bracket
  std::string first_sep, next_sep;  ///< before the first task element, before any later one
  std::string
      digest_open;  ///< after the bracket closing "tasks": the last member up to its 16 digits
  std::string digest_close;  ///< after the digits, to the end of the shard document

  ShardLayout() {
    std::string s;
    JsonWriter shard(s);
    shard.begin_object();
    shard.key("shard");
    shard_open = s;
    shard.null();
    std::size_t mark = s.size();
    shard.key("imuconv_version");
    shard_close = s.substr(mark);
    s.clear();
    JsonWriter whole(s);
    whole.begin_object();
    whole.key("imuconv_version");
    whole_open = s;
    whole.null();
    mark = s.size();
    whole.key("tasks");
    whole.begin_array();
    tasks_open = s.substr(mark);
    first_sep = whole.element_separator(true);
    whole.skip_elements(1);
    next_sep = whole.element_separator(false);
    // The shard's trailing member, as run.cpp's Execute writes it.
    s.clear();
    JsonWriter tail(s);
    tail.begin_object();
    tail.key("tasks");
    tail.begin_array();
    tail.end_array();
    mark = s.size();
    tail.key("shard_fnv1a_64");
    tail.string(std::string(16, '0'));
    tail.end_object();
    s += "\n";
    const std::string member = s.substr(mark);
    const std::size_t digits = member.find(std::string(16, '0'));
    digest_open = member.substr(0, digits);
    digest_close = member.substr(digits + 16);
  }
  /// After n task elements, through the bracket that closes "tasks".
  static std::string close_tasks(std::size_t n) { return closing(n, false); }
  /// After n task elements, to the end of the document.
  static std::string close(std::size_t n) {
    return closing(n, true) + "\n";  // the run ends its text document with a newline
  }

 private:
  /// What the writer emits after n task elements: the bracket that closes "tasks" and, for the
  /// whole document, the brace that closes it.
  static std::string closing(std::size_t n, bool document) {
    std::string s;
    JsonWriter w(s);
    w.begin_object();
    w.key("tasks");
    w.begin_array();
    w.skip_elements(n);
    const std::size_t mark = s.size();
    w.end_array();
    if (document) w.end_object();
    return s.substr(mark);
  }
};

/// A shard file read front to back through a fixed buffer.
class ShardReader {
 public:
  explicit ShardReader(const std::string& file) : file_(file) {
    // Opened as every input is (input_file.h): a FIFO or a device is refused, never waited on,
    // also one swapped in after a check by name.
    try {
      in_ = std::make_unique<data::InputFile>(file);
    } catch (const ReadError& e) {
      throw ShardError(e.what());
    }
    size_ = in_->size();
    RegisterInputPath(file, "a shard");  // its role, for a refused output (input_registry.h)
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw ShardError(Printable(file_) + (offset_ ? " (byte " + std::to_string(offset_) + ")" : "") +
                     ": " + what);
  }

  /// The next byte, or -1 at the end.
  int get() {
    if (pos_ == len_) {
      if (at_end_) return -1;
      try {
        len_ = in_->read(buf_.data(), buf_.size());
      } catch (const ReadError&) {
        fail("could not be read");
      }
      pos_ = 0;
      if (len_ == 0) {
        at_end_ = true;
        return -1;
      }
    }
    ++offset_;
    const char c = buf_[pos_++];
    hash_.add(&c, 1);
    return static_cast<unsigned char>(c);
  }

  /// The file's size when it was opened.
  std::uint64_t size() const noexcept { return size_; }
  /// FNV-1a 64 of every byte read so far.
  const pipeline::Fnv1a64& hash() const noexcept { return hash_; }

  /// Reads exactly `text`; else fails with `mismatch`, or as truncated at the end.
  void expect(std::string_view text, const std::string& mismatch) {
    for (char c : text) {
      const int g = get();
      if (g < 0) fail("ends early (a truncated shard?)");
      if (g != static_cast<unsigned char>(c)) fail(mismatch);
    }
  }

  /// Appends the text up to and including `marker` to `out`; fails beyond `limit` bytes.
  void read_through(std::string_view marker, std::size_t limit, std::string& out,
                    const std::string& what) {
    while (out.size() < marker.size() ||
           out.compare(out.size() - marker.size(), marker.size(), marker) != 0) {
      const int g = get();
      if (g < 0) fail("ends before " + what + " (a truncated shard?)");
      out.push_back(static_cast<char>(g));
      if (out.size() > limit)
        fail("no " + what + " within its first " + std::to_string(limit) + " bytes");
    }
  }

  /// Passes one JSON object (brackets balanced outside strings, nested at most `max_depth`
  /// deep) to `sink` in pieces of at most 64 KiB; `what` names it in messages. Its contents
  /// are not otherwise checked.
  template <typename Sink>
  void copy_object(const Sink& sink, const std::string& what, int max_depth = 1 << 30) {
    std::string piece;
    if (get() != '{') fail("expected " + what + " (an object) here");
    piece.push_back('{');
    int depth = 1;
    bool in_string = false, escaped = false;
    while (depth > 0) {
      const int g = get();
      if (g < 0) fail("ends inside " + what + " (a truncated shard?)");
      const char c = static_cast<char>(g);
      piece.push_back(c);
      if (in_string) {
        if (escaped)
          escaped = false;
        else if (c == '\\')
          escaped = true;
        else if (c == '"')
          in_string = false;
      } else if (c == '"') {
        in_string = true;
      } else if (c == '{' || c == '[') {
        if (++depth > max_depth) fail(what + " is nested deeper than imuconv writes it");
      } else if (c == '}' || c == ']') {
        --depth;
      }
      if (piece.size() >= (std::size_t{1} << 16)) {
        sink(piece);
        piece.clear();
      }
    }
    sink(piece);
  }

  void expect_end() {
    if (get() >= 0) fail("has more text after the end of its document");
  }

 private:
  std::string file_;
  std::unique_ptr<data::InputFile> in_;
  bool at_end_ = false;
  std::vector<char> buf_ = std::vector<char>(std::size_t{1} << 16);
  std::size_t pos_ = 0, len_ = 0;
  std::uint64_t offset_ = 0, size_ = 0;
  pipeline::Fnv1a64 hash_;
};

constexpr std::size_t kShardMemberLimit = std::size_t{16}
                                          << 20;  // the inputs' list: a few lines per file
constexpr std::size_t kHeadLimit = std::size_t{64}
                                   << 20;  // version, description, noise, plugins, ranges

/// Reads a shard up to its first element (the reader is left there).
ShardHead ReadHead(ShardReader& r, const std::string& file, const ShardLayout& layout) {
  ShardHead h;
  h.file = file;
  r.expect(layout.shard_open,
           "not a shard: it does not begin with the member \"shard\" that imuconv run --shard K/N "
           "writes first");
  r.copy_object(
      [&](const std::string& piece) {
        h.shard_text += piece;
        if (h.shard_text.size() > kShardMemberLimit)
          r.fail("its \"shard\" member is longer than any imuconv writes");
      },
      "the \"shard\" member", 3);  // {"inputs": [{...}]}
  try {
    h.shard = pipeline::ParseJsonText(h.shard_text, file);
  } catch (const pipeline::ConfigError& e) {
    const pipeline::Issue& first = e.issues().front();
    r.fail("its \"shard\" member is not JSON as imuconv writes it: " +
           (first.pointer.empty() ? std::string() : "/shard" + Printable(first.pointer) + ": ") +
           first.message);
  } catch (const pipeline::ReadError& e) {
    r.fail(std::string("its \"shard\" member cannot be read as JSON: ") + e.what());
  }
  if (!h.shard.is_object()) r.fail("/shard: expected an object");
  const auto field = [&](const char* key, std::uint64_t& v) {
    const auto it = h.shard.find(key);
    if (it == h.shard.end() || !it->is_number_unsigned())
      r.fail(std::string("/shard/") + key + ": expected a count");
    v = it->get<std::uint64_t>();
  };
  field("index", h.index);
  field("count", h.count);
  field("tasks", h.tasks);
  field("first_task", h.first);
  field("end_task", h.end);
  if (!h.shard.contains("inputs") || !h.shard["inputs"].is_array())
    r.fail("/shard/inputs: expected an array");
  if (h.count == 0 || h.index >= h.count || h.first > h.end || h.end > h.tasks)
    r.fail("its \"shard\" member is inconsistent (index " + std::to_string(h.index) + " of " +
           std::to_string(h.count) + ", tasks [" + std::to_string(h.first) + ", " +
           std::to_string(h.end) + ") of " + std::to_string(h.tasks) + ")");
  // A count read from the file is checked against the file's size before anything is sized by
  // it: each of its elements takes at least the two bytes of "{}".
  if ((h.end - h.first) > r.size() / 2)
    r.fail("its \"shard\" member says it holds " + std::to_string(h.end - h.first) +
           " task elements, more than its " + std::to_string(r.size()) + " bytes can hold");
  r.expect(layout.shard_close,
           "expected the key \"imuconv_version\" right after the \"shard\" member");
  r.read_through(layout.tasks_open, kHeadLimit, h.head, "the \"tasks\" array");
  return h;
}

/// The first line where two texts differ (1-based).
std::size_t FirstDifferentLine(const std::string& a, const std::string& b) {
  const std::size_t n = std::min(a.size(), b.size());
  std::size_t i = 0;
  while (i < n && a[i] == b[i]) ++i;
  return 1 + static_cast<std::size_t>(
                 std::count(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(i), '\n'));
}

/// That every shard comes from one run of one split, and that together they are all of it.
/// Returns them in shard order.
std::vector<const ShardHead*> CheckShards(const std::vector<ShardHead>& heads) {
  const ShardHead& a = heads.front();
  const auto other = [&](const ShardHead& h, const std::string& what) {
    throw ShardError(Printable(h.file) + " and " + Printable(a.file) +
                     " are not shards of one run: " + what);
  };
  // By index; a map, since a header may claim any number of shards (the count is checked
  // against the shards given before anything is sized by it).
  std::map<std::uint64_t, const ShardHead*> by_index;
  for (const ShardHead& h : heads) {
    if (h.count != a.count)
      other(h, "one is shard " + std::to_string(h.index) + " of " + std::to_string(h.count) +
                   ", the other of " + std::to_string(a.count));
    if (h.tasks != a.tasks)
      other(h, "their pipelines have " + std::to_string(h.tasks) + " and " +
                   std::to_string(a.tasks) + " tasks");
    if (h.shard["inputs"] != a.shard["inputs"])
      other(h,
            "their input files (the pipeline, its data) differ in name, size or FNV-1a hash "
            "(/shard/inputs)");
    if (const json here = h.shard.value("kernel_instance", json()),
        there = a.shard.value("kernel_instance", json());
        here != there)
      other(h,
            "they were computed by different SIMD instances of the kernels "
            "(/shard/kernel_instance: " +
                Printable(here.dump()) + " and " + Printable(there.dump()) +
                "), which round the last bits differently; run every shard on one kind of CPU");
    if (!h.head_as_first && h.head != a.head)
      other(h,
            "their documents differ before \"tasks\" at line " +
                std::to_string(1 + FirstDifferentLine(h.head, a.head)) +
                " (another pipeline path, imuconv version, gravity, noise, plugins or data range)");
    if (const auto seen = by_index.find(h.index); seen != by_index.end())
      throw ShardError("shard " + std::to_string(h.index) + " of " + std::to_string(h.count) +
                       " is given twice: " + Printable(seen->second->file) + " and " +
                       Printable(h.file));
    by_index[h.index] = &h;
  }
  if (const std::string missing = MissingShards(
          a.count, by_index.size(), [&](std::uint64_t k) { return by_index.count(k) > 0; });
      !missing.empty())
    throw ShardError(missing + "; every shard K/N of the run is needed (N is /shard/count of " +
                     Printable(a.file) + ")");
  std::vector<const ShardHead*> ordered;
  for (const auto& [index, h] : by_index) ordered.push_back(h);
  std::uint64_t end = 0;
  for (const ShardHead* h : ordered) {
    if (h->first != end)
      throw ShardError(Printable(h->file) + ": its tasks start at " + std::to_string(h->first) +
                       ", not where the previous shard's end (" + std::to_string(end) + ")");
    end = h->end;
  }
  if (end != a.tasks)
    throw ShardError("the shards hold tasks up to " + std::to_string(end) + " of " +
                     std::to_string(a.tasks));
  return ordered;
}

/// Reads a shard's elements (the reader is past its head) to its end, handing each element's
/// text to `element(k, piece)`, and checks the hash its last member records.
template <typename Element>
void ReadElementsAndDigest(ShardReader& r, const ShardHead& h, const ShardLayout& layout,
                           const Element& element) {
  for (std::uint64_t k = h.first; k < h.end; ++k) {
    r.expect(k == h.first ? layout.first_sep : layout.next_sep,
             "expected task " + std::to_string(k) + "'s element here (the shard holds tasks [" +
                 std::to_string(h.first) + ", " + std::to_string(h.end) + "))");
    r.copy_object([&](const std::string& piece) { element(k, piece); },
                  "task " + std::to_string(k) + "'s element",
                  static_cast<int>(pipeline::kMaxJsonDepth));
  }
  r.expect(ShardLayout::close_tasks(h.end - h.first),
           "expected the end of the \"tasks\" array after task " + std::to_string(h.end) +
               " (a shard holding other tasks than its \"shard\" member says?)");
  const std::string computed = r.hash().hex();
  r.expect(layout.digest_open,
           "expected the member \"shard_fnv1a_64\" after \"tasks\" (the hash of the shard's "
           "content that imuconv run "
           "--shard K/N writes last)");
  std::string written;
  for (int i = 0; i < 16; ++i) {
    const int g = r.get();
    if (g < 0) r.fail("ends inside /shard_fnv1a_64 (a truncated shard?)");
    written.push_back(static_cast<char>(g));
  }
  r.expect(layout.digest_close,
           "expected the end of the document after /shard_fnv1a_64 (16 hexadecimal digits)");
  r.expect_end();
  if (written != computed)
    r.fail(
        "is corrupted or was edited: its content does not match the FNV-1a 64 hash in "
        "/shard_fnv1a_64 (" +
        Printable(written) + " written, " + computed + " read)");
}

}  // namespace

std::string MissingShards(std::uint64_t count, std::uint64_t given,
                          const std::function<bool(std::uint64_t)>& is_given) {
  const std::uint64_t n_missing = count - given;
  std::string missing;
  for (std::uint64_t k = 0, listed = 0; k < count && listed < 20 && n_missing > 0; ++k)
    if (!is_given(k)) {
      missing += (missing.empty() ? "" : ", ") + std::to_string(k);
      ++listed;
    }
  if (!n_missing) return "";
  return "missing " + std::to_string(n_missing) + " of the " + std::to_string(count) +
         " shards (index " + missing + (n_missing > 20 ? ", ..." : "") + ")";
}

RunShards CheckRunShards(const std::vector<std::string>& files) {
  if (files.empty()) throw ShardError("no shard given");
  const ShardLayout layout;
  RunShards set;
  for (const auto& file : files) {
    ShardReader r(file);
    set.heads.push_back(ReadHead(r, file, layout));
    // Every element is read and the shard's hash checked now, before anything is written.
    ReadElementsAndDigest(r, set.heads.back(), layout, [](std::uint64_t, const std::string&) {});
    if (set.heads.size() > 1 && set.heads.back().head == set.heads.front().head) {
      set.heads.back().head_as_first = true;
      std::string().swap(set.heads.back().head);
    }
  }
  for (const ShardHead* h : CheckShards(set.heads))
    set.order.push_back(static_cast<std::size_t>(h - set.heads.data()));
  return set;
}

std::uint64_t JoinRunShards(const RunShards& set,
                            const std::function<void(std::string_view)>& write) {
  const ShardLayout layout;
  const std::string& head = set.heads.front().head;
  write(layout.whole_open);
  write(head);
  std::uint64_t written = 0;
  for (const std::size_t i : set.order) {
    const ShardHead* h = &set.heads[i];
    // Read again from the start: the file must still be the one checked.
    ShardReader r(h->file);
    const ShardHead again = ReadHead(r, h->file, layout);
    if (again.shard_text != h->shard_text || again.head != head)
      r.fail("changed while it was being merged");
    std::uint64_t current = h->end;  // no element started yet
    ReadElementsAndDigest(r, *h, layout, [&](std::uint64_t k, const std::string& piece) {
      if (k != current) {
        write(written == 0 ? layout.first_sep : layout.next_sep);
        current = k;
        ++written;
      }
      write(piece);
    });
  }
  write(ShardLayout::close(written));
  return written;
}

}  // namespace imuconv::pipeline
