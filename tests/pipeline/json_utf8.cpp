// JSON text is UTF-8 (issue 22): the one writer of imuconv's JSON documents (JsonWriter) refuses a
// string or key that is not, naming the output pointer, instead of copying its bytes raw into a
// document that then is not JSON; and a pipeline whose path is not UTF-8 (the head's
// /pipeline) is refused with no output written. The reader side: the one JSON reader refuses
// such bytes in a document (nlohmann's lexer), with the file named and no library id.
#include <gtest/gtest.h>

#include <string>

#include "imuconv/pipeline/json_parse.h"
#include "imuconv/pipeline/json_writer.h"
#include "imuconv/utf8.h"
#include "pipeline_test_util.h"

namespace {
using namespace imuconv;
using namespace imuconv::pipeline;
using imuconv::test::TempDir;
namespace fs = std::filesystem;

/// The message of writing {"name": value} (or {key: 1}), "" if it writes.
std::string WriteError(const std::string& key, const std::string& value, JsonWriter::Form form) {
  std::string out;
  JsonWriter w(out, 0, {}, JsonWriter::NonFinite::Throw, form);
  try {
    w.begin_object();
    w.key("tasks");
    w.begin_array();
    w.begin_object();
    w.key(key);
    w.string(value);
    w.end_object();
    w.end_array();
    w.end_object();
  } catch (const Error& e) {
    return e.what();
  }
  // What was written is JSON and holds the value unchanged.
  if (form == JsonWriter::Form::kText) {
    EXPECT_EQ(json::parse(out)["tasks"][0][key], value) << out;
  }
  return "";
}

TEST(JsonUtf8, TheWriterRefusesBytesThatAreNotUtf8AtTheirPointer) {
  for (const auto form : {JsonWriter::Form::kText, JsonWriter::Form::kEvents}) {
    SCOPED_TRACE(form == JsonWriter::Form::kText ? "text" : "events");
    // Well-formed: ASCII, 2-, 3- and 4-byte sequences, the largest code point.
    for (const char* ok :
         {"rk4", "caf\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x98\x80", "\xf4\x8f\xbf\xbf"})
      EXPECT_EQ(WriteError("name", ok, form), "") << ok;
    // Latin-1 "é": the example of the issue.
    std::string e = WriteError("name", "caf\xe9", form);
    EXPECT_NE(e.find("not UTF-8 (output /tasks/0/name, byte 3 of 'caf\\xe9')"), std::string::npos)
        << e;
    // Overlong "/" (C0 AF), overlong 3-byte NUL (E0 80 80), a surrogate (ED A0 80), above
    // U+10FFFF (F4 90 80 80), a stray continuation byte, a truncated sequence.
    for (const char* bad : {"a\xc0\xaf", "a\xe0\x80\x80", "a\xed\xa0\x80", "a\xf4\x90\x80\x80",
                            "a\x80", "a\xe2\x82"}) {
      e = WriteError("name", bad, form);
      EXPECT_NE(e.find("not UTF-8 (output /tasks/0/name, byte 1 of"), std::string::npos) << e;
    }
    // A key: its own pointer.
    e = WriteError("na\xffme", "x", form);
    EXPECT_NE(e.find("not UTF-8 (output /tasks/0/na\\xffme, byte 2"), std::string::npos) << e;
  }
}

TEST(JsonUtf8, FirstInvalidUtf8FindsTheFirstBadByte) {
  EXPECT_EQ(FirstInvalidUtf8(""), std::string_view::npos);
  EXPECT_EQ(FirstInvalidUtf8("ascii \x7f"), std::string_view::npos);
  EXPECT_EQ(FirstInvalidUtf8("\xc3\xa9\xc3"), 2u);      // a 2-byte sequence cut at the end
  EXPECT_EQ(FirstInvalidUtf8("\xc1\xbf"), 0u);          // overlong 2-byte form of U+007F
  EXPECT_EQ(FirstInvalidUtf8("\xf0\x8f\xbf\xbf"), 0u);  // overlong 4-byte form of U+FFFF
  EXPECT_EQ(FirstInvalidUtf8("\xf5\x80\x80\x80"), 0u);  // a lead byte no code point has
}

TEST(JsonUtf8, APipelineWhosePathIsNotUtf8WritesNoDocument) {
  TempDir tmp;
  const std::string dir = tmp.file("caf\xe9");
  fs::create_directory(dir);
  const std::string p = dir + "/P.json";
  fs::copy_file(imuconv::test::SourcePath("examples/inline_basics.json"), p);
  const std::string out = tmp.file("out.json");
  const test::CommandResult r =
      test::RunImuconv("-q run " + test::ShellQuote(p) + " -o " + test::ShellQuote(out), tmp);
  EXPECT_NE(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("not UTF-8 (output /pipeline, byte"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));  // before: written, and not JSON
}

TEST(JsonUtf8, TheReaderRefusesADocumentThatIsNotUtf8NamingTheFile) {
  TempDir tmp;
  const std::string f = tmp.write("bad.json", "{\"name\": \"caf\xe9\"}");
  const std::string m = test::MessageOf<ConfigError>([&] { (void)ParseJsonFile(f); });
  ASSERT_FALSE(m.empty()) << "a document that is not UTF-8 was read";
  EXPECT_NE(m.find("bad.json"), std::string::npos) << m;
  EXPECT_NE(m.find("not valid JSON"), std::string::npos) << m;
  EXPECT_EQ(m.find("[json.exception"), std::string::npos) << m;
}

}  // namespace
