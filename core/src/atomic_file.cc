#include "groundline/core/atomic_file.h"

#include <unistd.h>

#include <fstream>
#include <string>
#include <system_error>

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

}  // namespace groundline::core
