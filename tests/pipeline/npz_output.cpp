// imuconv run -o OUT.npz: the archive read back by a reader written here (ZIP central
// directory, ZIP64 records, CRC-32 computed bit by bit, .npy 1.0 headers), against the JSON
// output of the same run, number by number and bit for bit; the key rule on hand-written
// documents; the output-safety rules for the new format.
//
// Every comparison of numbers is exact (the 64 bits): the arrays must hold the doubles the JSON
// text reads back to, and the JSON writer prints the shortest text that does. There is no
// tolerance anywhere in this file.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <vector>

#include "../../apps/pipeline/src/io/npz_writer.h"
#include "imuconv/pipeline/result_arrays.h"
#include "pipeline_test_util.h"

namespace imuconv::test {
namespace {

using nlohmann::json;
using pipeline::CollectResultArrays;
using pipeline::NdArray;
using pipeline::ResultArrays;

// ---- an independent reader: ZIP (APPNOTE 6.3) and .npy 1.0 ----

std::uint64_t Le(const std::string& s, std::size_t at, int bytes) {
  if (at + static_cast<std::size_t>(bytes) > s.size())
    throw std::runtime_error("read past the end of the archive");
  std::uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i)
    v = (v << 8) | static_cast<unsigned char>(s[at + static_cast<std::size_t>(i)]);
  return v;
}

/// CRC-32 one bit at a time (the writer uses a table): the definition, not the same code.
std::uint32_t BitwiseCrc32(const std::string& s) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (unsigned char c : s) {
    crc ^= c;
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

struct NpyArray {
  std::string descr;
  std::vector<std::size_t> shape;
  std::string data;  ///< the raw bytes after the header
  bool zip64 = false;
};

struct Archive {
  std::vector<std::string> order;  ///< member names without ".npy", in central-directory order
  std::map<std::string, NpyArray> arrays;
  bool zip64_end = false;
};

NpyArray ParseNpy(const std::string& bytes, const std::string& name) {
  NpyArray a;
  if (bytes.compare(0, 8, std::string("\x93NUMPY\x01\x00", 8)) != 0)
    throw std::runtime_error(name + ": not .npy 1.0");
  const std::size_t header_len = Le(bytes, 8, 2);
  if ((10 + header_len) % 64 != 0)
    throw std::runtime_error(name + ": header not padded to 64 bytes");
  const std::string header = bytes.substr(10, header_len);
  if (header.back() != '\n')
    throw std::runtime_error(name + ": header does not end with a newline");
  const auto field = [&](const std::string& key) {
    const std::size_t at = header.find("'" + key + "': ");
    if (at == std::string::npos) throw std::runtime_error(name + ": no " + key);
    return at + key.size() + 4;
  };
  const std::size_t d = field("descr") + 1;
  a.descr = header.substr(d, header.find('\'', d) - d);
  if (header.compare(field("fortran_order"), 5, "False") != 0)
    throw std::runtime_error(name + ": Fortran order");
  const std::size_t s = field("shape");
  const std::string tuple = header.substr(s + 1, header.find(')', s) - s - 1);
  for (std::size_t i = 0; i < tuple.size();) {
    const std::size_t comma = tuple.find(',', i);
    const std::string n =
        tuple.substr(i, comma == std::string::npos ? std::string::npos : comma - i);
    if (n.find_first_not_of(' ') != std::string::npos) a.shape.push_back(std::stoull(n));
    if (comma == std::string::npos) break;
    i = comma + 1;
  }
  a.data = bytes.substr(10 + header_len);
  return a;
}

Archive ReadArchive(const std::string& z) {
  Archive ar;
  // The writer adds no archive comment: the end record is the last 22 bytes.
  if (z.size() < 22 || Le(z, z.size() - 22, 4) != 0x06054b50u)
    throw std::runtime_error("no end of central directory");
  const std::size_t eocd = z.size() - 22;
  std::uint64_t count = Le(z, eocd + 10, 2), cd_size = Le(z, eocd + 12, 4),
                cd_offset = Le(z, eocd + 16, 4);
  if (eocd >= 20 && Le(z, eocd - 20, 4) == 0x07064b50u) {  // the ZIP64 locator, then its record
    ar.zip64_end = true;
    const std::size_t rec = Le(z, eocd - 20 + 8, 8);
    if (Le(z, rec, 4) != 0x06064b50u || rec + 56 != eocd - 20)
      throw std::runtime_error("bad ZIP64 end record");
    count = Le(z, rec + 32, 8);
    cd_size = Le(z, rec + 40, 8);
    cd_offset = Le(z, rec + 48, 8);
  }
  if (cd_offset + cd_size > z.size()) throw std::runtime_error("central directory past the end");
  std::size_t at = cd_offset;
  for (std::uint64_t i = 0; i < count; ++i) {
    if (Le(z, at, 4) != 0x02014b50u) throw std::runtime_error("bad central directory entry");
    const std::uint64_t method = Le(z, at + 10, 2), crc = Le(z, at + 16, 4);
    std::uint64_t csize = Le(z, at + 20, 4), usize = Le(z, at + 24, 4), offset = Le(z, at + 42, 4);
    const std::size_t name_len = Le(z, at + 28, 2), extra_len = Le(z, at + 30, 2),
                      comment_len = Le(z, at + 32, 2);
    const std::string name = z.substr(at + 46, name_len);
    bool zip64 = false;
    for (std::size_t e = at + 46 + name_len; e + 4 <= at + 46 + name_len + extra_len;) {
      const std::uint64_t id = Le(z, e, 2), len = Le(z, e + 2, 2);
      std::size_t f = e + 4;
      if (id == 0x0001) {
        zip64 = true;
        if (usize == 0xFFFFFFFFu) usize = Le(z, f, 8), f += 8;
        if (csize == 0xFFFFFFFFu) csize = Le(z, f, 8), f += 8;
        if (offset == 0xFFFFFFFFu) offset = Le(z, f, 8), f += 8;
      }
      e += 4 + len;
    }
    if (method != 0 || csize != usize) throw std::runtime_error(name + ": not stored");
    if (Le(z, offset, 4) != 0x04034b50u || z.compare(offset + 30, name_len, name) != 0)
      throw std::runtime_error(name + ": bad local header");
    const std::size_t data_at = offset + 30 + Le(z, offset + 26, 2) + Le(z, offset + 28, 2);
    if (data_at + usize > z.size()) throw std::runtime_error(name + ": data past the end");
    const std::string bytes = z.substr(data_at, usize);
    if (BitwiseCrc32(bytes) != crc) throw std::runtime_error(name + ": CRC-32 mismatch");
    if (name.size() < 4 || name.compare(name.size() - 4, 4, ".npy") != 0)
      throw std::runtime_error(name + ": not .npy");
    const std::string key = name.substr(0, name.size() - 4);
    NpyArray a = ParseNpy(bytes, name);
    a.zip64 = zip64;
    ar.order.push_back(key);
    if (!ar.arrays.emplace(key, std::move(a)).second) throw std::runtime_error(name + ": twice");
    at += 46 + name_len + extra_len + comment_len;
  }
  return ar;
}

/// The sidecar's text: a 0-d "<U{n}" array, UTF-32LE (ASCII here).
json Sidecar(const Archive& ar) {
  const NpyArray& m = ar.arrays.at("meta");
  EXPECT_TRUE(m.shape.empty());
  EXPECT_EQ(m.descr, "<U" + std::to_string(m.data.size() / 4));
  std::string text;
  for (std::size_t i = 0; i < m.data.size(); i += 4) {
    EXPECT_EQ(Le(m.data, i, 4) < 0x80, true);
    text += static_cast<char>(Le(m.data, i, 4));
  }
  return json::parse(text);
}

std::uint64_t Bits(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, 8);
  return b;
}

std::string Escape(const std::string& s) {
  std::string e;
  for (char c : s)
    e += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return e;
}

/// The shape of a rectangular array of numbers with at least one number; false otherwise.
bool Rectangular(const json& v, std::vector<std::size_t>& shape) {
  if (v.is_number()) return !v.is_number_unsigned() || v.get<std::uint64_t>() <= INT64_MAX;
  if (!v.is_array() || v.empty()) return false;
  std::vector<std::size_t> first;
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::vector<std::size_t> s;
    if (!Rectangular(v[i], s) || (i > 0 && s != first)) return false;
    if (i == 0) first = s;
  }
  shape = {v.size()};
  shape.insert(shape.end(), first.begin(), first.end());
  return true;
}

void Flatten(const json& v, std::vector<const json*>& out) {
  if (v.is_array())
    for (const auto& e : v) Flatten(e, out);
  else
    out.push_back(&v);
}

/// Checks, for every value of the JSON document, that the archive holds it where the rule says:
/// a number in arrays at its key (the slice at its indices) or, when the key is written per
/// element, under its own pointer; anything else in the sidecar at its key or pointer. Counts
/// the numbers and the sidecar entries met, so that nothing in the archive is unaccounted for.
class Matcher {
 public:
  Matcher(const Archive& ar, const json& sidecar) : ar_(ar), values_(sidecar.at("values")) {}

  void Walk(const json& v, const std::string& key, const std::string& pointer,
            std::vector<std::size_t> index, std::vector<std::size_t> dims, bool top = false) {
    if (v.is_object()) {
      if (v.empty() && !top) return Value(v, key, pointer, index);
      for (auto it = v.begin(); it != v.end(); ++it) {
        const std::string m = Escape(it.key());
        if (top && it.key() == "tasks" && it->is_array() && !it->empty() &&
            it->front().is_object()) {
          for (const auto& task : *it) {
            const std::string name = "tasks/" + Escape(task.at("name").get<std::string>());
            Walk(task, name, name, index, dims);
          }
          continue;
        }
        Walk(*it, key.empty() ? m : key + "/" + m, pointer.empty() ? m : pointer + "/" + m, index,
             dims);
      }
      return;
    }
    if (v.is_array() && !v.empty() && v.front().is_object()) {
      dims.push_back(v.size());
      index.push_back(0);
      for (std::size_t i = 0; i < v.size(); ++i) {
        index.back() = i;
        Walk(v[i], key, pointer + "/" + std::to_string(i), index, dims);
      }
      return;
    }
    std::vector<std::size_t> shape;
    if (!Rectangular(v, shape) || (shape.empty() && index.empty()))
      return Value(v, key, pointer, index);
    Numbers(v, key, pointer, index, dims, shape);
  }

  std::size_t numbers = 0;
  std::set<std::string> arrays_met, values_met;

 private:
  void Value(const json& v, const std::string& key, const std::string& pointer,
             const std::vector<std::size_t>&) {
    const bool by_key = values_.contains(key), by_pointer = values_.contains(pointer);
    ASSERT_TRUE(by_key != by_pointer || key == pointer) << "sidecar value of /" << pointer;
    const json& got = values_.at(by_key ? key : pointer);
    EXPECT_TRUE(SameJson(got, v)) << "/" << pointer << ": " << got.dump() << " vs " << v.dump();
    values_met.insert(by_key ? key : pointer);
  }

  static bool SameJson(const json& a, const json& b) {
    if (a.type() != b.type()) return false;
    if (a.is_number_float()) return Bits(a.get<double>()) == Bits(b.get<double>());
    if (a.is_array() || a.is_object()) {
      if (a.size() != b.size()) return false;
      auto i = a.begin(), j = b.begin();
      for (; i != a.end(); ++i, ++j)
        if ((a.is_object() && i.key() != j.key()) || !SameJson(*i, *j)) return false;
      return true;
    }
    return a == b;
  }

  void Numbers(const json& v, const std::string& key, const std::string& pointer,
               const std::vector<std::size_t>& index, const std::vector<std::size_t>& dims,
               const std::vector<std::size_t>& shape) {
    const bool stacked = ar_.arrays.count(key) > 0, alone = ar_.arrays.count(pointer) > 0;
    ASSERT_TRUE(stacked != alone || key == pointer) << "no single array for /" << pointer;
    const NpyArray& a = ar_.arrays.at(stacked ? key : pointer);
    std::vector<std::size_t> want_shape = stacked ? dims : std::vector<std::size_t>{};
    want_shape.insert(want_shape.end(), shape.begin(), shape.end());
    ASSERT_EQ(a.shape, want_shape) << "/" << pointer;
    std::vector<const json*> flat;
    Flatten(v, flat);
    std::size_t cell = 0;  // the element's position in C order over the arrays of objects
    if (stacked)
      for (std::size_t j = 0; j < dims.size(); ++j) cell = cell * dims[j] + index[j];
    const std::size_t first = cell * flat.size();
    bool any_real = false;
    for (const json* x : flat) any_real = any_real || x->is_number_float();
    for (std::size_t i = 0; i < flat.size(); ++i) {
      const std::uint64_t bits = Le(a.data, 8 * (first + i), 8);
      if (a.descr == "<i8") {
        ASSERT_FALSE(any_real) << "/" << pointer << " holds reals but is int64";
        EXPECT_EQ(static_cast<std::int64_t>(bits), flat[i]->get<std::int64_t>())
            << "/" << pointer << " #" << i;
      } else {
        ASSERT_EQ(a.descr, "<f8") << "/" << pointer;
        EXPECT_EQ(bits, Bits(flat[i]->get<double>())) << "/" << pointer << " #" << i;
      }
    }
    numbers += flat.size();
    arrays_met.insert(stacked ? key : pointer);
  }

  const Archive& ar_;
  const json& values_;
};

/// Runs `pipeline` to JSON and to NPZ; checks the NPZ against the JSON; returns the archive.
Archive CheckPipeline(const std::string& pipeline, const TempDir& tmp,
                      std::size_t* numbers = nullptr) {
  const std::string out_json = tmp.file("out.json"), out_npz = tmp.file("out.npz");
  auto r = RunImuconv("run " + ShellQuote(pipeline) + " -q -o " + ShellQuote(out_json), tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = RunImuconv("run " + ShellQuote(pipeline) + " -q -o " + ShellQuote(out_npz), tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");  // -q: nothing on stdout; the archive went to the file
  const Archive ar = ReadArchive(ReadText(out_npz));
  const json doc = json::parse(ReadText(out_json));
  const json side = Sidecar(ar);
  EXPECT_EQ(side.at("format"), "imuconv-npz");
  EXPECT_EQ(side.at("format_version"), 1);
  Matcher m(ar, side);
  m.Walk(doc, "", "", {}, {}, true);
  // Every array of the archive and every sidecar value was met by a value of the document, and
  // the archive holds no number the document does not.
  EXPECT_EQ(m.arrays_met.size() + 1, ar.arrays.size());  // + the sidecar
  EXPECT_EQ(m.values_met.size(), side.at("values").size());
  std::size_t in_archive = 0;
  for (const auto& [k, a] : ar.arrays)
    if (k != "meta") in_archive += a.data.size() / 8;
  EXPECT_EQ(m.numbers, in_archive);
  if (numbers) *numbers = m.numbers;
  return ar;
}

TEST(NpzOutput, InlineBasicsEqualsTheJsonBitForBit) {
  TempDir tmp;
  std::size_t n = 0;
  const Archive ar = CheckPipeline(SourcePath("examples/inline_basics.json"), tmp, &n);
  EXPECT_GT(n, 1000u);  // its covariances and transition matrices alone are thousands of numbers
  EXPECT_FALSE(ar.zip64_end);
}

TEST(NpzOutput, KeyframesStackOverTheIntervals) {
  TempDir tmp;
  const Archive ar = CheckPipeline(SourcePath("examples/euroc_v1_01_keyframes.json"), tmp);
  // The pipeline asks for 10 Hz keyframes over 20 s: 200 intervals; J_bias is 9x6, cov 15x15.
  const NpyArray& jb = ar.arrays.at("tasks/kf_rk4/measurements/J_bias/matrix");
  EXPECT_EQ(jb.descr, "<f8");
  EXPECT_EQ(jb.shape, (std::vector<std::size_t>{200, 9, 6}));
  EXPECT_EQ(ar.arrays.at("tasks/kf_rk4/measurements/expressed/gtsam_manifold/cov/matrix").shape,
            (std::vector<std::size_t>{200, 15, 15}));
  // Absolute nanoseconds (beyond 2^53) stay integers.
  EXPECT_EQ(ar.arrays.at("tasks/kf_rk4/measurements/t_start_abs_ns").descr, "<i8");
  const json side = Sidecar(ar);
  EXPECT_EQ(side["values"]["tasks/kf_rk4/measurements/J_bias/rows/blocks"],
            json::parse(R"(["theta", "p", "v"])"));
  EXPECT_EQ(side["values"]["tasks/kf_rk4/type"], "preintegrate");
  EXPECT_EQ(side["stacked_over"]["tasks/kf_rk4/measurements/J_bias/matrix"],
            json::parse(R"(["tasks/kf_rk4/measurements"])"));
}

TEST(NpzOutput, GtsamImportEqualsTheJsonBitForBit) {
  TempDir tmp;
  CheckPipeline(SourcePath("examples/gtsam_import.json"), tmp);
}

TEST(NpzOutput, FormatFlagWritesTheSameArchiveAsTheExtension) {
  TempDir tmp;
  const std::string p = ShellQuote(SourcePath("examples/inline_basics.json"));
  ASSERT_EQ(RunImuconv("run " + p + " -q -o " + ShellQuote(tmp.file("a.npz")), tmp).exit_code, 0);
  ASSERT_EQ(RunImuconv("run " + p + " -q --format npz -o " + ShellQuote(tmp.file("b.data")), tmp)
                .exit_code,
            0);
  EXPECT_EQ(ReadText(tmp.file("a.npz")),
            ReadText(tmp.file("b.data")));  // and the same twice: no time stamps
  // --format json wins over the extension.
  ASSERT_EQ(RunImuconv("run " + p + " -q --format json -o " + ShellQuote(tmp.file("c.npz")), tmp)
                .exit_code,
            0);
  EXPECT_TRUE(json::accept(ReadText(tmp.file("c.npz"))));
  // To stdout when it is not a terminal (here a file), with -o -.
  const auto r = RunImuconv("run " + p + " -q --format npz -o -", tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, ReadText(tmp.file("a.npz")));
}

// ---- the rule, on hand-written documents ----

ResultArrays Collect(const std::string& text) { return CollectResultArrays(text, "doc"); }

const NdArray& Find(const ResultArrays& r, const std::string& key) {
  for (const auto& [k, a] : r.arrays)
    if (k == key) return a;
  throw std::runtime_error("no array " + key);
}

std::vector<std::string> Keys(const ResultArrays& r) {
  std::vector<std::string> k;
  for (const auto& e : r.arrays) k.push_back(e.first);
  return k;
}

TEST(ResultArrays, StacksOverNestedArraysOfObjects) {
  const ResultArrays r = Collect(R"({"top": 7, "labels": ["p", "q"], "a": [
      {"x": [1.5, 2], "n": 1, "s": "u", "in": [{"y": 0.25}, {"y": -0.0}]},
      {"x": [3.0, 4.0], "n": 2, "s": "u", "in": [{"y": 1e300}, {"y": 5e-324}]}]})");
  EXPECT_EQ(Keys(r), (std::vector<std::string>{"a/x", "a/n", "a/in/y"}));
  const NdArray& x = Find(r, "a/x");  // the integer 2 among reals: a real, exactly
  EXPECT_EQ(x.type, NdArray::Type::kFloat64);
  EXPECT_EQ(x.shape, (std::vector<std::size_t>{2, 2}));
  EXPECT_EQ(x.data, (std::vector<double>{1.5, 2.0, 3.0, 4.0}));
  const NdArray& n = Find(r, "a/n");
  EXPECT_EQ(n.type, NdArray::Type::kInt64);
  EXPECT_EQ(n.integers, (std::vector<std::int64_t>{1, 2}));
  const NdArray& y = Find(r, "a/in/y");
  EXPECT_EQ(y.shape, (std::vector<std::size_t>{2, 2}));
  ASSERT_EQ(y.data.size(), 4u);
  EXPECT_EQ(Bits(y.data[1]), Bits(-0.0));
  EXPECT_EQ(y.data[2], 1e300);
  EXPECT_EQ(Bits(y.data[3]), 1u);  // the smallest subnormal
  const json side = json::parse(r.sidecar);
  EXPECT_EQ(side["values"], json::parse(R"({"top": 7, "labels": ["p", "q"], "a/s": "u"})"));
  EXPECT_EQ(side["stacked_over"],
            json::parse(R"({"a/x": ["a"], "a/n": ["a"], "a/in/y": ["a", "a/in"]})"));
}

TEST(ResultArrays, IrregularKeysArePerElementNeverPadded) {
  const ResultArrays r =
      Collect(R"({"a": [{"t": 1.0, "m": [[1, 2]], "s": "x"}, {"m": [[1, 2], [3, 4]], "s": "y"}],
      "b": [{"in": [{"y": 1.0}]}, {"in": [{"y": 2.0}, {"y": 3.0}]}], "c": [[1.0], [2.0, 3.0]]})");
  EXPECT_EQ(Keys(r), (std::vector<std::string>{"a/0/t", "a/0/m", "a/1/m", "b/0/in/0/y",
                                               "b/1/in/0/y", "b/1/in/1/y"}));
  EXPECT_TRUE(Find(r, "a/0/t").shape.empty());
  EXPECT_EQ(Find(r, "a/0/m").shape, (std::vector<std::size_t>{1, 2}));
  EXPECT_EQ(Find(r, "a/1/m").integers, (std::vector<std::int64_t>{1, 2, 3, 4}));
  EXPECT_EQ(Find(r, "b/1/in/1/y").data, std::vector<double>{3.0});
  const json side = json::parse(r.sidecar);
  // Strings that differ per element, and a ragged array of numbers, go to the sidecar as they are.
  EXPECT_EQ(side["values"],
            json::parse(R"({"a/0/s": "x", "a/1/s": "y", "c": [[1.0], [2.0, 3.0]]})"));
  EXPECT_EQ(side["stacked_over"], json::object());
}

TEST(ResultArrays, TasksAreNamedAndMembersEscaped) {
  const ResultArrays r = Collect(
      R"({"tasks": [{"name": "t1", "v": [1.0]}, {"name": "t.2", "v": [2.0, 3.0]}], "a/b": {"c~d": [0.5], "e": {}}})");
  EXPECT_EQ(Keys(r), (std::vector<std::string>{"tasks/t1/v", "tasks/t.2/v", "a~1b/c~0d"}));
  EXPECT_EQ(Find(r, "tasks/t.2/v").shape, (std::vector<std::size_t>{2}));
  const json side = json::parse(r.sidecar);
  EXPECT_EQ(side["values"],
            json::parse(R"({"tasks/t1/name": "t1", "tasks/t.2/name": "t.2", "a~1b/e": {}})"));
}

TEST(ResultArrays, RefusesWhatItCannotMapWithThePointer) {
  const auto error = [](const std::string& text) {
    return MessageOf<imuconv::Error>([&] { (void)Collect(text); });
  };
  EXPECT_NE(error(R"({"tasks": [{"type": "x", "name": "t"}]})")
                .find("doc: /tasks/0: expected the task's \"name\""),
            std::string::npos);
  EXPECT_NE(error(R"({"tasks": [{"name": "t"}, {"name": "t"}]})").find("a second task named 't'"),
            std::string::npos);
  EXPECT_NE(error(R"({"a": [{"x": 1}, 2]})").find("/a/1: expected an object"), std::string::npos);
  EXPECT_NE(error(R"({"a": [1.0], "a": [2.0]})").find("/a: a duplicate key"), std::string::npos);
  EXPECT_NE(error(R"({"a": [{"x": [9007199254740993, 0.5]}]})").find("not exact as a double"),
            std::string::npos);
  EXPECT_NE(error(R"({"a": [1.0)").find("doc: /: not a JSON document"), std::string::npos);
  EXPECT_NE(error(R"([1.0])").find("expected an object at the top"), std::string::npos);
  EXPECT_NE(error(R"({"meta": [1.0]})").find("the sidecar's name"), std::string::npos);
  const std::string deep = "{\"a\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  EXPECT_NE(error(deep).find("doc: /: nested deeper than 256 levels"), std::string::npos);
  const std::string deep_objects = "{\"tasks\": [{\"name\": \"t\", \"a\": [" +
                                   std::string(300, '[') + "{\"b\": 1}" + std::string(300, ']') +
                                   "]}]}";
  EXPECT_NE(error(deep_objects).find("nested deeper than 256 levels"), std::string::npos);
}

// ---- the writer's ZIP64 form, read here and by numpy.load ----

TEST(NpzWriter, Zip64RecordsReadBack) {
  ResultArrays r = Collect(R"({"a": [{"x": [1.0, -2.5]}, {"x": [3.0, 4.0]}], "n": [1, 2, 3]})");
  std::string classic, zip64;
  pipeline::WriteResultNpz(r, [&](std::string_view s) { classic += s; });
  pipeline::WriteResultNpz(
      r, [&](std::string_view s) { zip64 += s; }, true);
  for (const std::string* z : {&classic, &zip64}) {
    const Archive ar = ReadArchive(*z);
    EXPECT_EQ(ar.zip64_end, z == &zip64);
    EXPECT_EQ(ar.order, (std::vector<std::string>{"a/x", "n", "meta"}));
    for (const auto& [k, a] : ar.arrays) EXPECT_EQ(a.zip64, z == &zip64) << k;
    EXPECT_EQ(ar.arrays.at("a/x").shape, (std::vector<std::size_t>{2, 2}));
    EXPECT_EQ(Le(ar.arrays.at("a/x").data, 8, 8), Bits(-2.5));
    EXPECT_EQ(ar.arrays.at("n").descr, "<i8");
    EXPECT_EQ(Le(ar.arrays.at("n").data, 16, 8), 3u);
  }
  // numpy.load is the reader that counts: Debian's python3 with python3-numpy.
  if (std::system("/usr/bin/python3 -c 'import numpy' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "/usr/bin/python3 with NumPy is not installed";
  TempDir tmp;
  const std::string path = tmp.write("z64.npz", zip64);
  const std::string script =
      "import numpy as np, json, sys\n"
      "z = np.load(sys.argv[1])\n"
      "assert z['a/x'].tolist() == [[1.0, -2.5], [3.0, 4.0]] and z['a/x'].dtype.str == '<f8'\n"
      "assert z['n'].tolist() == [1, 2, 3] and z['n'].dtype.str == '<i8'\n"
      "assert json.loads(str(z['meta']))['stacked_over'] == {'a/x': ['a']}\n";
  const std::string py = tmp.write("check.py", script);
  EXPECT_EQ(std::system(("/usr/bin/python3 " + ShellQuote(py) + " " + ShellQuote(path)).c_str()),
            0);
}

TEST(NpzWriter, NpyHeaderIsAlignedAndCrcIsZips) {
  EXPECT_EQ(pipeline::NpyHeader("<f8", {}).size() % 64, 0u);
  EXPECT_NE(pipeline::NpyHeader("<f8", {3}).find("'shape': (3,), }"), std::string::npos);
  EXPECT_NE(pipeline::NpyHeader("<i8", {2, 9, 6}).find("'shape': (2, 9, 6), }"), std::string::npos);
  // The check value of CRC-32/ISO-HDLC (the catalogue's "123456789" test vector).
  EXPECT_EQ(pipeline::Crc32(0, "123456789", 9), 0xCBF43926u);
  const std::string s = "a longer text, split in two";
  EXPECT_EQ(pipeline::Crc32(pipeline::Crc32(0, s.data(), 10), s.data() + 10, s.size() - 10),
            BitwiseCrc32(s));
}

/// The writer's CRC-32 before it read eight bytes at a time: one lookup in a 256-entry table per
/// byte. Kept here as the second reference for the slicing-by-8 version.
std::uint32_t ByteTableCrc32(const unsigned char* p, std::size_t n) {
  std::uint32_t table[256];
  for (std::uint32_t i = 0; i < 256; ++i) {
    std::uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  std::uint32_t crc = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFFu] ^ (crc >> 8);
  return ~crc;
}

TEST(NpzWriter, Crc32MatchesZlibAndTheByteWiseCrc) {
  // Values of zlib's crc32 (Python's zlib.crc32, zlib 1.2.13) for inputs shorter than, equal to
  // and longer than the eight bytes the writer folds at a time.
  const auto crc = [](const std::string& s) { return pipeline::Crc32(0, s.data(), s.size()); };
  EXPECT_EQ(crc(""), 0x00000000u);
  EXPECT_EQ(crc("a"), 0xE8B7BE43u);
  EXPECT_EQ(crc("abc"), 0x352441C2u);
  EXPECT_EQ(crc("The quick brown fox jumps over the lazy dog"), 0x414FA339u);
  EXPECT_EQ(crc(std::string(32, '\0')), 0x190A55ADu);
  EXPECT_EQ(crc(std::string(32, '\xFF')), 0xFF6CAB0Bu);
  std::string all(256, '\0');
  for (int i = 0; i < 256; ++i) all[static_cast<std::size_t>(i)] = static_cast<char>(i);
  EXPECT_EQ(crc(all), 0x29058C73u);

  // Random buffers of every length up to 80 and a few long ones, at every alignment of the start
  // (0-7 bytes into the buffer), whole and split at a random point: exactly the bit-wise
  // definition's and the byte-wise table's CRC (integer arithmetic: no tolerance).
  std::mt19937_64 rng(20261126);
  std::vector<std::size_t> lengths;
  for (std::size_t n = 0; n <= 80; ++n) lengths.push_back(n);
  for (std::size_t n : {1000u, 4099u, 65536u + 13u}) lengths.push_back(n);
  for (std::size_t n : lengths) {
    std::string buffer(n + 8, '\0');
    for (char& c : buffer) c = static_cast<char>(rng() & 0xFFu);
    for (std::size_t shift = 0; shift < 8; ++shift) {
      const std::string s = buffer.substr(shift, n);
      const std::uint32_t expected = BitwiseCrc32(s);
      ASSERT_EQ(ByteTableCrc32(reinterpret_cast<const unsigned char*>(s.data()), n), expected) << n;
      EXPECT_EQ(pipeline::Crc32(0, buffer.data() + shift, n), expected)
          << "length " << n << ", shift " << shift;
      const std::size_t cut = n == 0 ? 0 : static_cast<std::size_t>(rng() % (n + 1));
      EXPECT_EQ(pipeline::Crc32(pipeline::Crc32(0, s.data(), cut), s.data() + cut, n - cut),
                expected)
          << "length " << n << ", cut at " << cut;
    }
  }
}

// ---- output safety ----

TEST(NpzOutput, HostileDestinationsAndOptions) {
  TempDir tmp;
  const std::string p = ShellQuote(SourcePath("examples/inline_basics.json"));
  // --format npz with nowhere to write: refused before any work.
  auto r = RunImuconv("run " + p + " -q --format npz", tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--format npz: give the output file with -o"), std::string::npos) << r.err;
  EXPECT_EQ(r.out, "");
  r = RunImuconv("run " + p + " -q --format xml -o " + ShellQuote(tmp.file("x")), tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--format: expected json or npz"), std::string::npos) << r.err;
  // A directory named like an archive.
  fs::create_directory(tmp.file("dir.npz"));
  r = RunImuconv("run " + p + " -q -o " + ShellQuote(tmp.file("dir.npz")), tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("dir.npz"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(tmp.file("dir.npz")));
  // The pipeline itself as the output: refused, the pipeline untouched.
  const std::string copy =
      tmp.write("pipe.json", ReadText(SourcePath("examples/inline_basics.json")));
  r = RunImuconv("run " + ShellQuote(copy) + " -q --format npz -o " + ShellQuote(copy), tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(ReadText(copy), ReadText(SourcePath("examples/inline_basics.json")));
  // A failing run leaves an existing archive as it was, and no temporary beside it.
  const std::string bad = tmp.write(
      "bad.json", R"({"gravity": [0, 0, -9.81], "tasks": [{"type": "nope", "name": "x"}]})");
  const std::string old = tmp.write("old.npz", "the old content");
  const std::size_t entries = tmp.entries();
  r = RunImuconv("run " + ShellQuote(bad) + " -q -o " + ShellQuote(old), tmp);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_EQ(ReadText(old), "the old content");
  EXPECT_EQ(tmp.entries(), entries);
  // A character device that is not a terminal is written through.
  r = RunImuconv("run " + p + " -q -o /dev/null --format npz", tmp);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // A successful run replaces it.
  r = RunImuconv("run " + p + " -q -o " + ShellQuote(old), tmp);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NO_THROW((void)ReadArchive(ReadText(old)));
  EXPECT_EQ(tmp.entries(), entries);
}

TEST(NpzOutput, NeverToATerminal) {
  // script(1) (util-linux, essential on Debian) runs the command with a pseudo-terminal as its
  // stdout; -e returns the command's exit status.
  if (std::system("command -v script > /dev/null 2>&1") != 0) GTEST_SKIP() << "no script(1)";
  TempDir tmp;
  const std::string cmd = "env -u IMUCONV_PLUGIN_PATH " + Binary() + " run " +
                          SourcePath("examples/inline_basics.json") + " -q --format npz -o -";
  const std::string log = tmp.file("log");
  const int status = std::system(
      ("script -qec " + ShellQuote(cmd) + " /dev/null > " + ShellQuote(log) + " 2>&1").c_str());
  EXPECT_NE(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0);
  const std::string text = ReadText(log);
  EXPECT_NE(text.find("NPZ is binary: not written to a terminal"), std::string::npos) << text;
  EXPECT_EQ(text.find("PK"), std::string::npos);  // no archive bytes reached it
}

}  // namespace
}  // namespace imuconv::test
