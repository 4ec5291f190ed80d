#pragma once
// The one way core and the Lua layer write files: into a temporary file in the
// target folder, then rename over the target. A failed or interrupted write
// leaves the previous file (if any) untouched and no partial file behind.
#include <string>

namespace bliskrun {

// Writes `contents` to `path` atomically. Creates missing parent folders.
// Throws Error naming the path and the system reason on failure.
void write_file_atomic(const std::string& path, const std::string& contents);

// Removes the temporary files of writes still in progress. For a process
// about to end abruptly (the watchdog's hard stop), so that it leaves nothing
// half-written behind; safe to call from another thread.
void remove_unfinished_writes();

}  // namespace bliskrun
