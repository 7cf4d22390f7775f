// Did-you-mean for the command line's parse failures (usage_hint.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace imuconv::cli {

/// After the option parser failed on argv: "unknown subcommand 'chek' (did you mean 'check'?); the
/// subcommands are: ..." or "unknown option '--trails' for 'imuconv nees' (did you mean
/// '--trials'?); ...", naming the first word of argv that is neither a subcommand nor an option
/// where it stands; "" when every word is known (the parser's own message then says what failed).
std::string UsageHint(CLI::App& app, int argc, const char* const* argv);

}  // namespace imuconv::cli
