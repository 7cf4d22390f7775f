// The temporaries this process has open, for the signal handler that removes them
// (RemoveTemporariesOnSignal, output_file.h): a fixed table an OutputFile enters its temporary
// in while it exists.
#pragma once

#include <string>

namespace imuconv::pipeline::live_temporaries {

/// Enters `path`; returns its slot, or -1 when the table is full or the path too long (the file
/// is then only removed by its OutputFile, not on a signal).
int Remember(const std::string& path);
/// Leaves slot `slot` (-1: nothing).
void Forget(int slot);

}  // namespace imuconv::pipeline::live_temporaries
