// imuconv merge -o OUT.json SHARD.json...: joins the N outputs of `imuconv run P.json --shard K/N` (given in any
// order) into the document `imuconv run P.json` writes, byte for byte (examples/batch/).
//
// A shard is the whole run's document with a first member "shard" (its index, the split, the
// inputs' sizes and hashes) and only its block of tasks. The pipeline's JsonWriter writes every
// task element with the same text whatever its index (the splicing its thread pool relies on),
// so the merge copies text: the head once, then each shard's elements in shard order, with
// the separators and closing brackets the writer itself gives for their place. Nothing is parsed
// but the small "shard" member; the elements are streamed through a fixed buffer, one shard
// file open at a time, so memory does not grow with the shards' size.
//
// Refused, each with the file named (exit 2, no output written): a file that is not a shard, a
// truncated one, shards of different splits or of another pipeline, imuconv version, plugins,
// data (the heads before "tasks" differ) or inputs (sizes and FNV-1a hashes differ), shards
// computed by kernel instances that round differently (/shard/kernel_instance), a shard given
// twice, a missing one. A montecarlo shard is pointed to imuconv montecarlo --merge.
#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "commands.h"
#include "imuconv/pipeline/json_check.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/pipeline/output_file.h"
#include "imuconv/printable.h"
#include "shard.h"

namespace imuconv::cli {
namespace {

using pipeline::json;
using pipeline::JsonWriter;

/// The fixed text between the pieces, as the pipeline's JsonWriter lays out a run's document
/// (apps/pipeline/src/run.cpp: the "shard" member, the head whose first key is
/// "imuconv_version", then "tasks").
struct Layout {
  std::string shard_open;           ///< the shard document's text before the "shard" member's value
  std::string shard_close;          ///< after that value, up to the head's first value
  std::string whole_open;           ///< the whole document's text before the head's first value
  std::string tasks_open;           ///< the end of the head: the "tasks" key and its bracket
  std::string first_sep, next_sep;  ///< before the first task element, before any later one

  Layout() {
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
  }
  /// After n task elements, to the end of the document.
  static std::string close(std::size_t n) {
    std::string s;
    JsonWriter w(s);
    w.begin_object();
    w.key("tasks");
    w.begin_array();
    w.skip_elements(n);
    const std::size_t mark = s.size();
    w.end_array();
    w.end_object();
    return s.substr(mark) + "\n";  // the run ends its text document with a newline
  }
};

/// A shard file read front to back through a fixed buffer.
class ShardReader {
 public:
  explicit ShardReader(const std::string& file) : file_(file) {
    struct stat st {};
    if (stat(file.c_str(), &st) != 0) fail("cannot be read (no such file?)");
    if (!S_ISREG(st.st_mode)) fail("is not a regular file");
    in_.open(file, std::ios::binary);
    if (!in_) fail("cannot be opened");
    pipeline::RegisterInputPath(file, "a shard");  // no output may replace it (input_registry.h)
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw UsageError{"merge: " + Printable(file_) + (offset_ ? " (byte " + std::to_string(offset_) + ")" : "") + ": " +
                     what};
  }

  /// The next byte, or -1 at the end.
  int get() {
    if (pos_ == len_) {
      if (in_.bad() || in_.eof()) return -1;
      in_.read(buf_.data(), static_cast<std::streamsize>(buf_.size()));
      len_ = static_cast<std::size_t>(in_.gcount());
      pos_ = 0;
      if (in_.bad()) fail("could not be read");
      if (len_ == 0) return -1;
    }
    ++offset_;
    return static_cast<unsigned char>(buf_[pos_++]);
  }

  /// Reads exactly `text`; else fails with `mismatch`, or as truncated at the end.
  void expect(std::string_view text, const std::string& mismatch) {
    for (char c : text) {
      const int g = get();
      if (g < 0) fail("ends early (a truncated shard?)");
      if (g != static_cast<unsigned char>(c)) fail(mismatch);
    }
  }

  /// Appends the text up to and including `marker` to `out`; fails beyond `limit` bytes.
  void read_through(std::string_view marker, std::size_t limit, std::string& out, const std::string& what) {
    while (out.size() < marker.size() || out.compare(out.size() - marker.size(), marker.size(), marker) != 0) {
      const int g = get();
      if (g < 0) fail("ends before " + what + " (a truncated shard?)");
      out.push_back(static_cast<char>(g));
      if (out.size() > limit) fail("no " + what + " within its first " + std::to_string(limit) + " bytes");
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
  std::ifstream in_;
  std::vector<char> buf_ = std::vector<char>(std::size_t{1} << 16);
  std::size_t pos_ = 0, len_ = 0;
  std::uint64_t offset_ = 0;
};

/// What a shard says of itself, and its text up to its first task element.
struct ShardHead {
  std::string file;
  std::string shard_text, head;  ///< the "shard" member's value; the head through "tasks": [
  bool head_as_first = false;    ///< the head is the first shard's (then not kept twice)
  json shard;
  std::uint64_t index = 0, count = 0, tasks = 0, first = 0, end = 0;
};

constexpr std::size_t kShardMemberLimit = std::size_t{16} << 20;  // the inputs' list: a few lines per file
constexpr std::size_t kHeadLimit = std::size_t{64} << 20;         // version, description, noise, plugins, ranges

/// Reads a shard up to its first element (the reader is left there).
ShardHead ReadHead(ShardReader& r, const std::string& file, const Layout& layout) {
  ShardHead h;
  h.file = file;
  r.expect(layout.shard_open,
           "not a shard: it does not begin with the member \"shard\" that imuconv run --shard K/N writes first");
  r.copy_object(
      [&](const std::string& piece) {
        h.shard_text += piece;
        if (h.shard_text.size() > kShardMemberLimit) r.fail("its \"shard\" member is longer than any imuconv writes");
      },
      "the \"shard\" member", 3);  // {"inputs": [{...}]}
  try {
    h.shard = json::parse(h.shard_text);
  } catch (const std::exception& e) {
    r.fail(std::string("its \"shard\" member is not JSON: ") + e.what());
  }
  const auto field = [&](const char* key, std::uint64_t& v) {
    const auto it = h.shard.find(key);
    if (it == h.shard.end() || !it->is_number_unsigned()) r.fail(std::string("/shard/") + key + ": expected a count");
    v = it->get<std::uint64_t>();
  };
  field("index", h.index);
  field("count", h.count);
  field("tasks", h.tasks);
  field("first_task", h.first);
  field("end_task", h.end);
  if (!h.shard.contains("inputs") || !h.shard["inputs"].is_array()) r.fail("/shard/inputs: expected an array");
  if (h.count == 0 || h.index >= h.count || h.first > h.end || h.end > h.tasks)
    r.fail("its \"shard\" member is inconsistent (index " + std::to_string(h.index) + " of " + std::to_string(h.count) +
           ", tasks [" + std::to_string(h.first) + ", " + std::to_string(h.end) + ") of " + std::to_string(h.tasks) +
           ")");
  r.expect(layout.shard_close, "expected the key \"imuconv_version\" right after the \"shard\" member");
  r.read_through(layout.tasks_open, kHeadLimit, h.head, "the \"tasks\" array");
  return h;
}

/// The first line where two texts differ (1-based).
std::size_t FirstDifferentLine(const std::string& a, const std::string& b) {
  const std::size_t n = std::min(a.size(), b.size());
  std::size_t i = 0;
  while (i < n && a[i] == b[i]) ++i;
  return 1 + static_cast<std::size_t>(std::count(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(i), '\n'));
}

/// That every shard comes from one run of one split, and that together they are all of it.
/// Returns them in shard order.
std::vector<const ShardHead*> CheckShards(const std::vector<ShardHead>& heads) {
  const ShardHead& a = heads.front();
  const auto other = [&](const ShardHead& h, const std::string& what) {
    throw UsageError{"merge: " + Printable(h.file) + " and " + Printable(a.file) +
                     " are not shards of one run: " + what};
  };
  std::vector<const ShardHead*> by_index(a.count, nullptr);
  for (const ShardHead& h : heads) {
    if (h.count != a.count)
      other(h, "one is shard " + std::to_string(h.index) + " of " + std::to_string(h.count) + ", the other of " +
                   std::to_string(a.count));
    if (h.tasks != a.tasks)
      other(h, "their pipelines have " + std::to_string(h.tasks) + " and " + std::to_string(a.tasks) + " tasks");
    if (h.shard["inputs"] != a.shard["inputs"])
      other(h, "their input files (the pipeline, its data) differ in name, size or FNV-1a hash (/shard/inputs)");
    if (const json here = h.shard.value("kernel_instance", json()), there = a.shard.value("kernel_instance", json());
        here != there)
      other(h, "they were computed by different SIMD instances of the kernels (/shard/kernel_instance: " +
                   Printable(here.dump()) + " and " + Printable(there.dump()) +
                   "), which round the last bits differently; run every shard on one kind of CPU");
    if (!h.head_as_first && h.head != a.head)
      other(h, "their documents differ before \"tasks\" at line " +
                   std::to_string(1 + FirstDifferentLine(h.head, a.head)) +
                   " (another pipeline path, imuconv version, gravity, noise, plugins or data range)");
    if (const ShardHead* seen = by_index[h.index])
      throw UsageError{"merge: shard " + std::to_string(h.index) + " of " + std::to_string(h.count) +
                       " is given twice: " + Printable(seen->file) + " and " + Printable(h.file)};
    by_index[h.index] = &h;
  }
  std::string missing;
  std::size_t n_missing = 0;
  for (std::size_t k = 0; k < by_index.size(); ++k)
    if (!by_index[k] && ++n_missing <= 20) missing += (missing.empty() ? "" : ", ") + std::to_string(k);
  if (n_missing)
    throw UsageError{"merge: missing " + std::to_string(n_missing) + " of the " + std::to_string(a.count) +
                     " shards (index " + missing + (n_missing > 20 ? ", ..." : "") +
                     "); every shard K/N of the run is needed"};
  std::uint64_t end = 0;
  for (const ShardHead* h : by_index) {
    if (h->first != end)
      throw UsageError{"merge: " + Printable(h->file) + ": its tasks start at " + std::to_string(h->first) +
                       ", not where the previous shard's end (" + std::to_string(end) + ")"};
    end = h->end;
  }
  if (end != a.tasks)
    throw UsageError{"merge: the shards hold tasks up to " + std::to_string(end) + " of " + std::to_string(a.tasks)};
  return by_index;
}

struct Options {
  std::string output;
  std::vector<std::string> shards;
};

int Merge(const CommandContext& ctx, const Options& o) {
  const Layout layout;
  // First every shard's head: all are checked before anything is written.
  std::vector<ShardHead> heads;
  for (const auto& file : o.shards) {
    ShardReader r(file);
    {
      // A montecarlo shard has its own merge (it concludes statistics, it does not join text).
      std::ifstream in(file, std::ios::binary);
      std::string first(montecarlo::kShardMagic.size(), '\0');
      if (in.read(first.data(), static_cast<std::streamsize>(first.size())) && first == montecarlo::kShardMagic)
        throw UsageError{"merge: " + Printable(file) +
                         " is a shard of imuconv montecarlo --shard K/N: join those with imuconv montecarlo --merge"};
    }
    heads.push_back(ReadHead(r, file, layout));
    if (heads.size() > 1 && heads.back().head == heads.front().head) {
      heads.back().head_as_first = true;
      std::string().swap(heads.back().head);
    }
  }
  const std::vector<const ShardHead*> ordered = CheckShards(heads);
  const std::string& head = heads.front().head;
  pipeline::OutputFile out(o.output);
  for (const auto& file : o.shards) out.refuse_if_same(file, "a shard");
  out.write(layout.whole_open);
  out.write(head);
  std::uint64_t written = 0;
  for (const ShardHead* h : ordered) {
    // Read again from the start: the file must still be the one checked.
    ShardReader r(h->file);
    const ShardHead again = ReadHead(r, h->file, layout);
    if (again.shard_text != h->shard_text || again.head != head) r.fail("changed while it was being merged");
    for (std::uint64_t k = h->first; k < h->end; ++k) {
      const bool first_here = k == h->first;
      r.expect(first_here ? layout.first_sep : layout.next_sep,
               "expected task " + std::to_string(k) + "'s element here (the shard holds tasks [" +
                   std::to_string(h->first) + ", " + std::to_string(h->end) + "))");
      out.write(written == 0 ? layout.first_sep : layout.next_sep);
      r.copy_object([&](const std::string& piece) { out.write(piece); }, "task " + std::to_string(k) + "'s element");
      ++written;
    }
    r.expect(Layout::close(h->end - h->first),
             "expected the end of the \"tasks\" array and of the document after task " + std::to_string(h->end) +
                 " (a shard holding other tasks than its \"shard\" member says?)");
    r.expect_end();
  }
  out.write(Layout::close(written));
  std::cout.flush();
  out.commit();
  if (!ctx.quiet() && !out.is_stdout())
    std::cout << "wrote " << Printable(o.output) << " (" << written << " task(s) from " << ordered.size()
              << " shard(s))\n";
  return 0;
}

}  // namespace

void RegisterMergeCommand(CLI::App& app, CommandContext& ctx) {
  auto* sub = app.add_subcommand(
      "merge",
      "Join the N outputs of imuconv run P.json --shard K/N (K = 0..N-1, in any order) into the document imuconv run "
      "P.json writes, byte for byte. Refused, naming the file, and nothing written: a missing or duplicate shard, a "
      "truncated one, shards of another split, pipeline, imuconv version, plugins or input data (examples/batch/)");
  static Options o;
  sub->add_option("-o,--output", o.output,
                  "Output file (replaced atomically, as imuconv run writes it; '-' is stdout); never one of the shards")
      ->required()
      ->type_name("OUT.json")
      ->check(OutputPathCheck());
  sub->add_option("shards", o.shards, "The shard outputs")->required()->type_name("SHARD.json");
  SetCommandAction(*sub, ctx, [&ctx] { return Merge(ctx, o); });
}

}  // namespace imuconv::cli
