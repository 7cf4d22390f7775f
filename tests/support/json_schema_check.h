// Asserts that JSON documents follow a schema of schemas/ (Draft 2020-12), with Debian's
// python3-jsonschema, as tests/pipeline/validate_schemas.py does for the pipeline cases: the
// schema itself is checked first, then every document; the first ten errors are printed.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "../pipeline/pipeline_test_util.h"

namespace imuconv::test {

/// `docs` is an array of documents; `name` names the files written into `tmp` (and the failure).
inline void ExpectFollowsSchema(const TempDir& tmp, const std::string& schema,
                                const nlohmann::json& docs, const std::string& name) {
  const std::string path = tmp.write(name + ".docs.json", docs.dump());
  const std::string script = tmp.write(
      "validate.py",
      "import json, sys\n"
      "from jsonschema import Draft202012Validator\n"
      "schema = json.load(open(sys.argv[1]))\n"
      "Draft202012Validator.check_schema(schema)\n"
      "v = Draft202012Validator(schema)\n"
      "bad = [e.message for doc in json.load(open(sys.argv[2])) for e in v.iter_errors(doc)]\n"
      "print('\\n'.join(bad[:10]))\n"
      "sys.exit(1 if bad else 0)\n");
  const std::string cmd = "/usr/bin/python3 " + ShellQuote(script) + " " +
                          ShellQuote(SourcePath(schema)) + " " + ShellQuote(path);
  EXPECT_EQ(std::system(cmd.c_str()), 0) << name << ": " << cmd;
}

}  // namespace imuconv::test
