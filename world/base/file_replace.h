#pragma once
// Files written whole or not at all: a writer fills a temporary beside its target and renames it
// over the target only once every byte is written and the close succeeded, so a full disk, a
// failed close or an error half-way (a block id that does not fit) leaves what was at the path
// before, and no cut file that a reader might take for a whole one. Any thread; one file per owner.

#include <cstdio>
#include <string>

#include "world/base/assert.h"
#include "world/base/result.h"
#include "world/base/stdio_file.h"

namespace vx::world {

// Creates a new empty file named `path` + ".tmp-" + 12 random hex digits, exclusively
// (O_CREAT | O_EXCL, mode 0666 less the umask: no other process's file or link is ever reused),
// and returns its name; the caller writes it and removes or renames it. Thread-safe.
Result<std::string> create_temp_beside(const std::string& path);

// Renames `from` over `to` (atomic on one file system, POSIX rename(2)); removes `from` on
// failure. Thread-safe.
Status replace_file(const std::string& from, const std::string& to);

// Where a whole-file write to `path` lands. Symbolic links are followed to the file they name
// (which may not exist yet), so the rename replaces or creates that file and the link stays a
// link. `in_place` when that exists and is not a regular file: a device such as /dev/stdout or
// /dev/full, a FIFO. A rename over one would replace the device itself (as root, in /dev), so it
// is written directly or refused. A loop of links is in place too (opening it fails). Any thread.
struct WriteTarget {
    std::string path;
    bool in_place = false;
};
WriteTarget write_target(const std::string& path);

// Gives `temp` the permission bits of `target` where that is a regular file, so a file replaced
// by a rename keeps its mode (an export kept private stays so). Best effort. Any thread.
void keep_permissions(const std::string& temp, const std::string& target);

// A file to be written at `path`, through a temporary beside it (beside the file a symbolic link
// names), renamed over it by commit(); a file replaced so keeps its permission bits. Where
// write_target says in place, it is written directly, as a device must be. Destroyed without a
// successful commit(), it removes its temporary. Move-only.
class ReplacingFile {
public:
    ReplacingFile() = default;
    ReplacingFile(ReplacingFile&& other) noexcept;
    ReplacingFile& operator=(ReplacingFile&&) noexcept;
    ~ReplacingFile();

    // Opens the file for writing (`mode` as fopen's: "w" or "wb"). Errors name `path`.
    Status open(const std::string& path, const char* mode);
    // The stream to write; null before open() and after commit().
    std::FILE* get() const { return m_file.get(); }
    // Flushes and closes the stream, both checked (see close_written); the path is not touched
    // yet. Files that belong together (an OBJ and its .mtl) finish all, then commit all, so only
    // a failed rename, not a full disk, can part them. On failure the temporary is removed.
    Status finish();
    // finish() if not yet done, then renames the temporary over the path. On any failure the
    // temporary is removed and the path keeps what it had.
    Status commit();

private:
    void discard();

    StdioFile m_file;
    std::string m_path;   // As given: errors name it.
    std::string m_target; // What the temporary is renamed over (a link's end).
    std::string m_temp;   // Empty: written in place.
    bool m_finished = false;
};

} // namespace vx::world
