// Atomic file output: the content is written to a temporary file in the same directory as `path`
// and renamed onto `path` only once it is complete and flushed, so a reader never sees a
// half-written result and an existing file is replaced in one step (POSIX rename). If `write`
// throws, or the stream fails, the temporary is removed and `path` is left as it was.
//
// Errors (cannot create the temporary, write failure, rename failure) throw InvalidInput with
// SourceLocation{path}. Exceptions thrown by `write` propagate unchanged.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace stickslip {

// Writes the file by calling write(stream); the stream is opened in binary mode (no newline
// translation) and uses the classic "C" locale.
void write_file_atomically(const std::string& path,
                           const std::function<void(std::ostream&)>& write);

}  // namespace stickslip
