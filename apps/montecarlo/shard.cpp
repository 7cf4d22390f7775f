// The montecarlo shard file (shard.h has its layout).
#include "shard.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <utility>

#include "imuconv/kernels/preintegration.h"
#include "imuconv/pipeline/file_digest.h"
#include "imuconv/pipeline/input_registry.h"
#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/shard_merge.h"
#include "imuconv/printable.h"

#ifndef IMUCONV_VERSION
#define IMUCONV_VERSION "unknown"
#endif

namespace imuconv::montecarlo {
namespace {

using nlohmann::json;

constexpr std::size_t kBytesPerTrial = sizeof(double) * kDim;
constexpr std::size_t kHeaderLimit = std::size_t{1}
                                     << 20;       // the header is ~8 KB (225 hex floats, a note)
constexpr std::size_t kTrailerSize = 9 + 16 + 1;  // "fnv1a_64 " + 16 hex digits + "\n"

/// A double as a C99 hexadecimal float: strtod reads it back to the same bits.
std::string HexFloat(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

[[noreturn]] void Bad(const std::string& pointer, const std::string& what) {
  throw Error("/run" + pointer + ": " + what);
}

const json& Member(const json& o, const char* key, const std::string& at) {
  const auto it = o.find(key);
  if (it == o.end()) Bad(at + "/" + key, "missing");
  return *it;
}

double HexFloatAt(const json& v, const std::string& at) {
  if (!v.is_string()) Bad(at, "expected a hexadecimal float string");
  const std::string& s = v.get_ref<const std::string&>();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size())
    Bad(at, "expected a hexadecimal float, found " + Printable(s));
  // imuconv writes finite numbers only (a NaN or an infinity would reach the verdict as one).
  if (!std::isfinite(x)) Bad(at, "expected a finite number, found " + Printable(s));
  return x;
}

std::string StringAt(const json& o, const char* key, const std::string& at) {
  const json& v = Member(o, key, at);
  if (!v.is_string()) Bad(at + "/" + key, "expected a string");
  return v.get<std::string>();
}

std::uint64_t CountAt(const json& o, const char* key, const std::string& at) {
  const json& v = Member(o, key, at);
  if (!v.is_number_unsigned()) Bad(at + "/" + key, "expected a count");
  return v.get<std::uint64_t>();
}

void PutLittleEndian(double x, char* out) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  for (int b = 0; b < 8; ++b) out[b] = static_cast<char>((u >> (8 * b)) & 0xff);
}

double GetLittleEndian(const char* in) {
  std::uint64_t u = 0;
  for (int b = 0; b < 8; ++b)
    u |= static_cast<std::uint64_t>(static_cast<unsigned char>(in[b])) << (8 * b);
  double x;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

/// The two first lines of a shard (magic, header) as written.
std::string HeadText(int index, int count, int first, int end, const json& run) {
  const json header = {
      {"shard", {{"index", index}, {"count", count}, {"first_trial", first}, {"end_trial", end}}},
      {"run", run},
      {"payload_bytes", static_cast<std::uint64_t>(end - first) * kBytesPerTrial}};
  return std::string(kShardMagic) + "\n" + header.dump() + "\n";
}

[[noreturn]] void FileFails(const std::string& file, const std::string& what) {
  throw Error(Printable(file) + ": " + what);
}

/// A JSON value in a message: short.
std::string Brief(const nlohmann::json& v) {
  std::string s = v.dump();
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return Printable(s);
}

}  // namespace

std::pair<int, int> ShardTrials(int trials, int index, int count) {
  const auto at = [&](int k) {
    return static_cast<int>(static_cast<long long>(k) * trials / count);
  };
  return {at(index), at(index + 1)};
}

json ShardProvenance(const Registry& reg, const PreintegrationMethod& method,
                     const std::string& convention, const std::string& case_path) {
  const pipeline::FileDigest case_digest = pipeline::DigestFile(case_path);
  json plugins = json::array();
  for (const PluginInfo* info :
       {&reg.info(method.kind, method.id), &reg.info(PluginKind::IncrementConvention, convention)})
    plugins.push_back({{"id", info->id}, {"file", info->file}, {"version", info->version}});
  return {
      {"imuconv_version", IMUCONV_VERSION},
      {"kernel_instance", kernels::IsaName(kernels::BestIsa())},
      {"case",
       {{"path", case_path}, {"bytes", case_digest.bytes}, {"fnv1a_64", case_digest.hash.hex()}}},
      {"plugins", plugins}};
}

json ShardRunJson(const Result& head, const json& provenance) {
  json predicted = json::array();
  for (int r = 0; r < kDim; ++r)
    for (int c = 0; c < kDim; ++c) predicted.push_back(HexFloat(head.predicted(r, c)));
  json blocks = json::array();
  for (const BlockRatio& b : head.blocks) blocks.push_back(b.block);
  json run = provenance;
  run.update(json{{"method", head.method},
                  {"method_kind", head.method_kind},
                  {"convention", head.convention},
                  {"trials", head.trials},
                  {"seed", head.seed},
                  {"noise_scale", HexFloat(head.noise_scale)},
                  {"samples", head.samples},
                  {"duration", HexFloat(head.duration)},
                  {"noise_model",
                   {{"simulated", head.noise_model.simulated},
                    {"matches_prediction", head.noise_model.matches},
                    {"note", head.noise_model.note}}},
                  {"blocks", blocks},
                  {"trial_path", head.trial_path},
                  {"mean_only_offset", HexFloat(head.mean_only_offset)},
                  {"predicted", predicted}});
  if (!head.mean_only_refused.empty()) run["mean_only_refused"] = head.mean_only_refused;
  return run;
}

Result ResultFromRunJson(const json& run) {
  if (!run.is_object()) Bad("", "expected an object");
  Result r;
  r.method = StringAt(run, "method", "");
  r.method_kind = StringAt(run, "method_kind", "");
  r.convention = StringAt(run, "convention", "");
  const std::uint64_t trials = CountAt(run, "trials", "");
  if (trials < static_cast<std::uint64_t>(kDim + 1) ||
      trials > static_cast<std::uint64_t>(kMaxTrials))
    Bad("/trials",
        "expected 16 to " + std::to_string(kMaxTrials) + ", found " + std::to_string(trials));
  r.trials = static_cast<int>(trials);
  r.seed = CountAt(run, "seed", "");
  r.noise_scale = HexFloatAt(Member(run, "noise_scale", ""), "/noise_scale");
  r.samples = static_cast<std::size_t>(CountAt(run, "samples", ""));
  r.duration = HexFloatAt(Member(run, "duration", ""), "/duration");
  const json& nm = Member(run, "noise_model", "");
  if (!nm.is_object()) Bad("/noise_model", "expected an object");
  r.noise_model.simulated = StringAt(nm, "simulated", "/noise_model");
  const json& matches = Member(nm, "matches_prediction", "/noise_model");
  if (!matches.is_boolean()) Bad("/noise_model/matches_prediction", "expected true or false");
  r.noise_model.matches = matches.get<bool>();
  r.noise_model.note = StringAt(nm, "note", "/noise_model");
  const json& blocks = Member(run, "blocks", "");
  if (!blocks.is_array() || blocks.size() != static_cast<std::size_t>(kBlockCount))
    Bad("/blocks", "expected the " + std::to_string(kBlockCount) + " block names");
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (!blocks[b].is_string()) Bad("/blocks/" + std::to_string(b), "expected a string");
    r.blocks.push_back(BlockRatio{blocks[b].get<std::string>(), 0.0, {}});
  }
  r.trial_path = StringAt(run, "trial_path", "");
  r.mean_only_offset = HexFloatAt(Member(run, "mean_only_offset", ""), "/mean_only_offset");
  if (run.contains("mean_only_refused"))  // written only where a mean-only path was refused
    r.mean_only_refused = StringAt(run, "mean_only_refused", "");
  const json& predicted = Member(run, "predicted", "");
  if (!predicted.is_array() || predicted.size() != static_cast<std::size_t>(kDim * kDim))
    Bad("/predicted", "expected the 225 entries of the predicted covariance, row by row");
  for (int i = 0; i < kDim * kDim; ++i)
    r.predicted(i / kDim, i % kDim) =
        HexFloatAt(predicted[static_cast<std::size_t>(i)], "/predicted/" + std::to_string(i));
  return r;
}

void WriteShard(const std::function<void(std::string_view)>& sink, int index, int count, int first,
                int end, const json& run, const std::vector<Vec15>& errors) {
  if (errors.size() != static_cast<std::size_t>(end - first))
    throw Error("montecarlo: " + std::to_string(errors.size()) + " end errors for trials [" +
                std::to_string(first) + ", " + std::to_string(end) + ")");
  pipeline::Fnv1a64 hash;
  const std::string head = HeadText(index, count, first, end, run);
  hash.add(head.data(), head.size());
  sink(head);
  std::string piece;
  piece.reserve(std::size_t{1} << 16);
  for (const Vec15& e : errors) {
    char bytes[kBytesPerTrial];
    for (int j = 0; j < kDim; ++j) PutLittleEndian(e[j], bytes + 8 * j);
    piece.append(bytes, sizeof bytes);
    if (piece.size() + kBytesPerTrial > (std::size_t{1} << 16)) {
      hash.add(piece.data(), piece.size());
      sink(piece);
      piece.clear();
    }
  }
  hash.add(piece.data(), piece.size());
  sink(piece);
  sink("fnv1a_64 " + hash.hex() + "\n");
}

ShardHeader ReadShardHeader(const std::string& file) {
  struct stat st {};
  if (stat(file.c_str(), &st) != 0) FileFails(file, "cannot be read (no such file?)");
  if (!S_ISREG(st.st_mode)) FileFails(file, "is not a regular file");
  std::ifstream in(file, std::ios::binary);
  if (!in) FileFails(file, "cannot be opened");
  pipeline::RegisterInputPath(file, "a shard");  // no output may replace it (input_registry.h)
  const std::string not_shard = "not a montecarlo shard: it does not begin with the line \"" +
                                std::string(kShardMagic) +
                                "\" that imuconv montecarlo --shard K/N -o FILE writes";
  std::string line;
  char c;
  while (line.size() <= kShardMagic.size() && in.get(c) && c != '\n') line.push_back(c);
  if (line != kShardMagic) {
    if (line.rfind("imuconv montecarlo shard ", 0) == 0)
      FileFails(file, "a montecarlo shard of another format version (\"" + Printable(line) +
                          "\"); this imuconv reads \"" + std::string(kShardMagic) + "\"");
    if (!line.empty() && line.front() == '{')
      FileFails(
          file,
          not_shard +
              " (it is JSON: the shards of imuconv run --shard K/N are merged by imuconv merge)");
    FileFails(file, not_shard);
  }
  std::string text;
  while (in.get(c) && c != '\n') {
    text.push_back(c);
    if (text.size() > kHeaderLimit)
      FileFails(file, "its header line is longer than any imuconv writes (" +
                          std::to_string(kHeaderLimit) + " bytes): a corrupted shard?");
  }
  if (!in) FileFails(file, "ends inside its header line (a truncated shard?)");
  json header;
  try {
    // The one JSON reader (its nesting bound keeps the copies below off a deep recursion).
    header = pipeline::ParseJsonText(text, file);
  } catch (const pipeline::ConfigError& e) {
    const pipeline::Issue& first = e.issues().front();
    FileFails(file, "its header line is not JSON as imuconv writes it (a corrupted shard?): " +
                        (first.pointer.empty() ? std::string() : Printable(first.pointer) + ": ") +
                        first.message);
  } catch (const pipeline::ReadError& e) {
    FileFails(file, std::string("its header line cannot be read as JSON (a corrupted shard?): ") +
                        e.what());
  }
  ShardHeader h;
  h.file = file;
  try {
    if (!header.is_object()) throw Error("/: expected an object");
    const auto shard = header.find("shard");
    if (shard == header.end() || !shard->is_object()) throw Error("/shard: expected an object");
    const auto field = [&](const char* key, int& v) {
      const auto it = shard->find(key);
      if (it == shard->end() || !it->is_number_unsigned() ||
          it->get<std::uint64_t>() > std::uint64_t{1} << 30)
        throw Error(std::string("/shard/") + key + ": expected a count");
      v = it->get<int>();
    };
    field("index", h.index);
    field("count", h.count);
    field("first_trial", h.first);
    field("end_trial", h.end);
    const auto run = header.find("run");
    if (run == header.end() || !run->is_object()) throw Error("/run: expected an object");
    h.run = *run;
    const Result r = ResultFromRunJson(h.run);  // checks its form now, before any trial is read
    if (h.count < 1 || h.index >= h.count ||
        std::make_pair(h.first, h.end) != ShardTrials(r.trials, h.index, h.count))
      throw Error("/shard: shard " + std::to_string(h.index) + " of " + std::to_string(h.count) +
                  " of " + std::to_string(r.trials) + " trials holds trials [" +
                  std::to_string(ShardTrials(r.trials, h.index, h.count).first) + ", " +
                  std::to_string(ShardTrials(r.trials, h.index, h.count).second) + "), not [" +
                  std::to_string(h.first) + ", " + std::to_string(h.end) + ")");
    const auto payload = header.find("payload_bytes");
    if (payload == header.end() || !payload->is_number_unsigned() ||
        payload->get<std::uint64_t>() !=
            static_cast<std::uint64_t>(h.end - h.first) * kBytesPerTrial)
      throw Error("/payload_bytes: expected " + std::to_string((h.end - h.first) * kBytesPerTrial) +
                  " (15 doubles for each of its trials)");
  } catch (const Error& e) {
    FileFails(file, std::string("its header is malformed (a corrupted shard?): ") + e.what());
  }
  h.payload_offset = kShardMagic.size() + 1 + text.size() + 1;
  const std::uint64_t expected = h.payload_offset +
                                 static_cast<std::uint64_t>(h.end - h.first) * kBytesPerTrial +
                                 kTrailerSize;
  const auto actual = static_cast<std::uint64_t>(st.st_size);
  if (actual < expected)
    FileFails(file, "is truncated: " + std::to_string(actual) + " bytes, where its " +
                        std::to_string(h.end - h.first) + " trials [" + std::to_string(h.first) +
                        ", " + std::to_string(h.end) + ") need " + std::to_string(expected));
  if (actual > expected)
    FileFails(file, "has " + std::to_string(actual - expected) + " bytes after its end (" +
                        std::to_string(expected) + " for its trials [" + std::to_string(h.first) +
                        ", " + std::to_string(h.end) + "))");
  return h;
}

void ReadShardErrors(const ShardHeader& h, Vec15* out) {
  std::ifstream in(h.file, std::ios::binary);
  if (!in) FileFails(h.file, "cannot be opened");
  const std::string expected_head = HeadText(h.index, h.count, h.first, h.end, h.run);
  std::string head(static_cast<std::size_t>(h.payload_offset), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  pipeline::Fnv1a64 hash;
  hash.add(head.data(), static_cast<std::size_t>(in.gcount()));
  // The header as this imuconv writes it: a header with the same values in another layout is
  // not one of ours (and its hash was taken over other bytes).
  const bool head_ok = in && head == expected_head;
  std::vector<char> buf(std::size_t{1} << 16);
  std::size_t trial = 0;
  const std::size_t trials = static_cast<std::size_t>(h.end - h.first);
  while (trial < trials) {
    const std::size_t n = std::min(trials - trial, buf.size() / kBytesPerTrial);
    in.read(buf.data(), static_cast<std::streamsize>(n * kBytesPerTrial));
    if (static_cast<std::size_t>(in.gcount()) != n * kBytesPerTrial)
      FileFails(h.file,
                "ends early (a truncated shard, or one that changed while it was being merged?)");
    hash.add(buf.data(), n * kBytesPerTrial);
    for (std::size_t t = 0; t < n; ++t)
      for (int j = 0; j < kDim; ++j)
        out[trial + t][j] = GetLittleEndian(buf.data() + t * kBytesPerTrial + 8 * j);
    trial += n;
  }
  std::string trailer(kTrailerSize, '\0');
  in.read(trailer.data(), static_cast<std::streamsize>(trailer.size()));
  if (static_cast<std::size_t>(in.gcount()) != kTrailerSize)
    FileFails(h.file, "ends before its hash line (a truncated shard?)");
  if (trailer.rfind("fnv1a_64 ", 0) != 0 || trailer.back() != '\n')
    FileFails(h.file, "its last line is not \"fnv1a_64 <16 hex digits>\" (a corrupted shard?)");
  if (!head_ok || trailer != "fnv1a_64 " + hash.hex() + "\n")
    FileFails(h.file,
              "is corrupted: its content does not match the FNV-1a 64 hash on its last line (" +
                  Printable(trailer.substr(9, 16)) + " written, " + hash.hex() + " read)");
  if (in.peek() != std::char_traits<char>::eof())
    FileFails(h.file, "has bytes after its hash line");
}

Result MergeShards(const std::vector<std::string>& files, std::string& case_path) {
  std::vector<ShardHeader> heads;
  for (const std::string& f : files) heads.push_back(montecarlo::ReadShardHeader(f));
  const ShardHeader& a = heads.front();
  // By index; a map, since a header may claim up to 2^30 shards (more than the trials is allowed).
  std::map<int, const ShardHeader*> by_index;
  for (const ShardHeader& h : heads) {
    const std::string other =
        Printable(h.file) + " and " + Printable(a.file) + " are not shards of one run: ";
    if (h.count != a.count)
      throw Error(other + "one is shard " + std::to_string(h.index) + " of " +
                  std::to_string(h.count) + ", the other of " + std::to_string(a.count));
    if (h.run != a.run) {
      for (auto it = a.run.begin(); it != a.run.end(); ++it) {
        const auto there = h.run.find(it.key());
        if (there == h.run.end() || *there != it.value())
          throw Error(other + "their /run/" + it.key() + " differ (" +
                      (there == h.run.end() ? std::string("missing") : Brief(*there)) + " and " +
                      Brief(it.value()) + ")");
      }
      throw Error(other + "their /run objects differ (a member only in " + Printable(h.file) + ")");
    }
    if (const auto seen = by_index.find(h.index); seen != by_index.end())
      throw Error("shard " + std::to_string(h.index) + " of " + std::to_string(h.count) +
                  " is given twice: " + Printable(seen->second->file) + " and " +
                  Printable(h.file));
    by_index[h.index] = &h;
  }
  if (const std::string missing = pipeline::MissingShards(
          static_cast<std::uint64_t>(a.count), by_index.size(),
          [&](std::uint64_t k) { return by_index.count(static_cast<int>(k)) > 0; });
      !missing.empty())
    throw Error(missing + "; every shard K/N of the run is needed");
  Result result;
  try {
    result = ResultFromRunJson(a.run);
  } catch (const std::exception& e) {
    throw Error(Printable(a.file) + ": " + e.what());
  }
  if (a.run.contains("case") && a.run["case"].is_object() && a.run["case"].contains("path") &&
      a.run["case"]["path"].is_string())
    case_path = a.run["case"]["path"].get<std::string>();
  // The trials' end errors, as the whole run holds them (ShardTrials: the shards tile [0, trials)).
  std::vector<Vec15> errors(static_cast<std::size_t>(result.trials), Vec15::Zero());
  for (const auto& [index, h] : by_index) ReadShardErrors(*h, errors.data() + h->first);
  try {
    Conclude(result, errors);
  } catch (const Error& e) {
    // Conclude knows no file: the shards' values are what it judged.
    std::string names;
    for (const auto& [index, h] : by_index)
      names += (names.empty() ? "" : ", ") + Printable(h->file);
    if (names.size() > 300) names = names.substr(0, 297) + "...";
    throw Error("the shards " + names + " (" + std::to_string(a.count) +
                " of one run): " + e.what());
  }
  return result;
}

}  // namespace imuconv::montecarlo
