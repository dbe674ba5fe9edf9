#include "groundline/core/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <string>
#include <system_error>
#include <utility>

namespace groundline::core {

Status WriteFileAtomically(const std::filesystem::path& path,
                           const std::function<Status(std::ostream&)>& write) {
  std::error_code ec;
  if (path.has_parent_path()) {
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) {
      return Status::Error("cannot create directory " + path.parent_path().string() + ": " +
                           ec.message());
    }
  }
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  Status status = Status::Ok();
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return Status::Error("cannot open " + tmp.string() + " for writing");
    status = write(out);
    out.flush();
    if (status.ok() && !out) status = Status::Error("write to " + tmp.string() + " failed");
  }
  if (status.ok()) {
    std::filesystem::rename(tmp, path, ec);
    if (ec)
      status = Status::Error("cannot rename " + tmp.string() + " to " + path.string() + ": " +
                             ec.message());
  }
  if (!status.ok()) std::filesystem::remove(tmp, ec);
  return status;
}

Status WriteFileAtomically(const std::filesystem::path& path, std::string_view contents) {
  return WriteFileAtomically(path, [contents](std::ostream& out) {
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    return Status::Ok();
  });
}

namespace {

// Moves every entry of `from` into `to` (which exists), merging folders.
Status MergeInto(const std::filesystem::path& from, const std::filesystem::path& to) {
  std::error_code ec;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(from, ec)) {
    const std::filesystem::path target = to / entry.path().filename();
    if (entry.is_directory() && std::filesystem::is_directory(target)) {
      if (Status s = MergeInto(entry.path(), target); !s.ok()) return s;
      continue;
    }
    if (std::filesystem::is_directory(target)) std::filesystem::remove_all(target, ec);
    std::filesystem::rename(entry.path(), target, ec);
    if (ec) {
      return Status::Error("cannot rename " + entry.path().string() + " to " + target.string() +
                           ": " + ec.message());
    }
  }
  if (ec) return Status::Error("cannot list " + from.string() + ": " + ec.message());
  return Status::Ok();
}

}  // namespace

StagedDirectory::StagedDirectory(std::filesystem::path final_dir, std::filesystem::path staging)
    : final_(std::move(final_dir)), staging_(std::move(staging)) {}

StagedDirectory::StagedDirectory(StagedDirectory&& other) noexcept
    : final_(std::move(other.final_)), staging_(std::move(other.staging_)) {
  other.staging_.clear();
}

StagedDirectory::~StagedDirectory() {
  if (staging_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(staging_, ec);
}

Result<StagedDirectory> StagedDirectory::Create(const std::filesystem::path& final_dir) {
  // Absolute, so that "out/", "." and ".." name a folder with a parent.
  std::filesystem::path final_path = std::filesystem::absolute(final_dir).lexically_normal();
  if (final_path.filename().empty()) final_path = final_path.parent_path();
  const std::filesystem::path parent = final_path.parent_path();
  std::error_code ec;
  std::filesystem::create_directories(parent, ec);
  if (ec) return Status::Error("cannot create directory " + parent.string() + ": " + ec.message());
  const std::filesystem::path staging =
      parent / ("." + final_path.filename().string() + ".tmp." + std::to_string(::getpid()));
  std::filesystem::remove_all(staging, ec);
  std::filesystem::create_directory(staging, ec);
  if (ec) {
    return Status::Error("cannot create the staging directory " + staging.string() + ": " +
                         ec.message());
  }
  return StagedDirectory(final_path, staging);
}

Status StagedDirectory::Commit() {
  if (staging_.empty()) return Status::Error("staged directory: already committed");
  std::error_code ec;
  Status status = Status::Ok();
  if (!std::filesystem::exists(final_)) {
    std::filesystem::rename(staging_, final_, ec);
    if (ec) {
      status = Status::Error("cannot rename " + staging_.string() + " to " + final_.string() +
                             ": " + ec.message());
    } else {
      staging_.clear();
      return status;
    }
  } else if (!std::filesystem::is_directory(final_)) {
    status = Status::Error(final_.string() + " exists and is not a directory");
  } else {
    status = MergeInto(staging_, final_);
  }
  std::filesystem::remove_all(staging_, ec);
  staging_.clear();
  return status;
}

}  // namespace groundline::core
