#pragma once
// The one way every command writes its outputs. A regular file (new, existing, or the target of a
// symlink) is replaced atomically through a temp file in its folder, keeping the old file's mode;
// a character device, a FIFO or "-" (stdout) is streamed to; anything else (a directory, a socket,
// a block device) is refused. The outputs of one command are one OutputSet: each is written to a
// temp first, and nothing is streamed or renamed until every one succeeded. Temp files are
// anonymous (O_TMPFILE) where the filesystem allows, else named kTempPrefix + 16 hex digits and
// held under flock, so a later run into the folder removes those a killed process left.
#include <relief/core/error.h>

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace relief {

inline constexpr std::string_view kTempPrefix = ".relief-tmp-";

class OutputSet {
  public:
    OutputSet();
    ~OutputSet();  // a set not committed removes its temps: nothing is written
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;

    // Checks what is at `path`, then runs write(tempPath) into a fresh temp file. After an error
    // the set is failed and commit() writes nothing.
    Status add(const std::string& path,
               const std::function<Status(const std::string& tempPath)>& write);
    Status addText(const std::string& path, std::string_view text);

    // Streams the device / FIFO / stdout outputs, then renames the temps into place.
    Status commit();

    struct Entry;

  private:
    std::vector<std::unique_ptr<Entry>> m_entries;
    bool m_failed = false;
    bool m_committed = false;
};

// True when `path` ends with `ext` (".npy"), letters in any case: output formats come from it.
bool hasExtension(std::string_view path, std::string_view ext);

// For tests (a full disk): called before each write relief makes itself and after each temp is
// filled; a nonzero return is taken as that errno.
using WriteFaultHook = std::function<int(const std::string& path)>;
void setWriteFaultHookForTesting(WriteFaultHook hook);

// For tests: false makes every temp a named one, as on a filesystem without O_TMPFILE.
void setAnonymousTempsForTesting(bool allowed);

// Flushes std::cout and stdout; an earlier or final write error (a closed stdout, a full disk, a
// closed pipe) is reported as "stdout: ...".
Status flushStdout();

// Removes temp files in `folder` that no live process holds (left by SIGKILL). Called by the
// first output into each folder; returns how many were removed.
int removeStaleTempFiles(const std::string& folder);

}  // namespace relief
