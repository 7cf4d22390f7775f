// Descriptors 0, 1 and 2 belong to standard input, output and error, even when they are closed.
//
// A program started with a standard descriptor closed (`imuconv run P.json -o out.json >&-`)
// would otherwise hand that number to the next file it opens: the temporary output would
// become descriptor 1, and the summary printed to std::cout would land inside the JSON
// document. Two defences, both used by every command and by the Python module:
//   - at start (main, the module's init), each closed standard descriptor is opened onto
//     /dev/null, so no file opened later can take its number;
//   - every file the tool opens itself (inputs, outputs, spools) is moved above 2 should it
//     still get one of them (a host process, such as Python, may close one at any time).
#pragma once

namespace imuconv::pipeline {

/// Opens /dev/null onto each of descriptors 0-2 that is closed. Throws imuconv::Error when one
/// is closed and /dev/null cannot be opened onto it.
void OpenClosedStandardDescriptors();

/// Whether descriptor `fd` (0-2) was closed when OpenClosedStandardDescriptors() ran: then it
/// is /dev/null, and an output naming it ("-", /dev/stdout) is refused rather than written
/// into nothing.
bool StandardDescriptorWasClosed(int fd) noexcept;

/// `fd` itself when it is above 2 (or negative: a failed open); else a close-on-exec duplicate
/// above 2, and `fd` is closed. A negative return with errno set when no duplicate can be made.
int AboveStandardDescriptors(int fd) noexcept;

}  // namespace imuconv::pipeline
