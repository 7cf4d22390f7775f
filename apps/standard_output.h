// Standard output, completed: what a command printed there (a table, a --json document, a
// summary) has reached it, or the command fails. std::cout buffers, and a write error (a full
// disk under `imuconv check --json > result.json`, a closed pipe with SIGPIPE ignored) may only
// show when the buffer is flushed, after the command has returned its exit code; unchecked, the
// result was lost and the exit code said 0. main() checks once, after every command, so a
// command needs nothing of its own (run's -o -, an OutputFile, reports its own write errors).
#pragma once

namespace imuconv::cli {

/// Called once, first thing in main: from then on std::cout remembers the first failed write to
/// standard output and its reason (errno then; by the end of the command errno says something
/// else). The text goes through as before, to C's stdout, nothing held on the way, so a fork
/// duplicates nothing more than it did.
void WatchStandardOutput();

/// Flushes std::cout and the C stream under it. Returns `exit_code` when everything printed
/// was written; otherwise prints "imuconv: error: standard output: cannot write the command's
/// output (REASON): it is incomplete" and returns kExitBadInput (2, as run -o - exits when its
/// document cannot be written), unless `exit_code` already says an internal error (3), kept.
[[nodiscard]] int CompleteStandardOutput(int exit_code);

}  // namespace imuconv::cli
