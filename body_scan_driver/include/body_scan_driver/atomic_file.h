// Atomic file writes: every file the suite writes (calibrations, reports, clouds) goes
// through here, so a reader never sees a half-written file and a crash loses nothing.
#pragma once

#include <stdexcept>
#include <string>

namespace body_scan_driver {

struct FileWriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Writes `contents` to a temporary file in the folder of `path` and renames it over `path`.
// Creates missing parent folders. Throws FileWriteError naming the file and the fix.
// owner_only: mode 0600 (personal data), from before the file holds anything.
void writeFileAtomically(const std::string& path, const std::string& contents,
                         bool owner_only = false);

}  // namespace body_scan_driver
