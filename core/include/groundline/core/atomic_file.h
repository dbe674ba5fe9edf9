// Writing files so that a reader never sees a half-written one: the content
// goes to "<path>.tmp.<pid>" in the same directory, is flushed, and is then
// renamed over <path> (atomic on POSIX file systems). A whole output folder
// the same way: StagedDirectory.
#ifndef GROUNDLINE_CORE_ATOMIC_FILE_H_
#define GROUNDLINE_CORE_ATOMIC_FILE_H_

#include <filesystem>
#include <functional>
#include <ostream>
#include <string_view>

#include "groundline/core/status.h"

namespace groundline::core {

// Calls `write` with a stream on the temporary file; renames it to `path` if
// `write` returns ok and the stream is good, else removes it and returns the error.
// Creates missing parent directories.
Status WriteFileAtomically(const std::filesystem::path& path,
                           const std::function<Status(std::ostream&)>& write);

Status WriteFileAtomically(const std::filesystem::path& path, std::string_view contents);

// An output folder that appears complete or not at all. A command writes
// into path(), a temporary sibling "<parent>/.<name>.tmp.<pid>" of the final
// folder, and calls Commit() once everything is written: when the final
// folder does not exist the staging folder is renamed to it (one atomic
// step); when it does, each staged entry is renamed over its namesake in it,
// folders merged entry by entry (each rename atomic; files the run did not
// write are kept). An uncommitted staging folder is removed by the
// destructor, so a run that fails leaves the final folder as it was.
// Not thread-safe; move-only.
class StagedDirectory {
 public:
  // Errors: the staging folder cannot be created (names it).
  static Result<StagedDirectory> Create(const std::filesystem::path& final_dir);
  StagedDirectory(StagedDirectory&& other) noexcept;
  StagedDirectory& operator=(StagedDirectory&&) = delete;
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();

  const std::filesystem::path& path() const { return staging_; }
  const std::filesystem::path& final_path() const { return final_; }
  // Errors: a rename failed (names both paths); what was renamed before it
  // stays in the final folder, the rest in the staging folder is removed.
  Status Commit();

 private:
  StagedDirectory(std::filesystem::path final_dir, std::filesystem::path staging);
  std::filesystem::path final_;
  std::filesystem::path staging_;  // empty once committed or moved from
};

}  // namespace groundline::core

#endif  // GROUNDLINE_CORE_ATOMIC_FILE_H_
