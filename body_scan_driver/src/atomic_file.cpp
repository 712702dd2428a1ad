#include <body_scan_driver/atomic_file.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <system_error>

namespace body_scan_driver {

void writeFileAtomically(const std::string& path, const std::string& contents, bool owner_only) {
  const std::filesystem::path target(path);
  std::error_code error;
  if (target.has_parent_path()) std::filesystem::create_directories(target.parent_path(), error);
  if (error)
    throw FileWriteError("cannot create the folder of '" + path + "' (" + error.message() +
                         "): choose a writable location");
  // Same folder as the target, so the rename cannot cross file systems.
  const std::string temporary = path + ".tmp" + std::to_string(::getpid());
  if (owner_only) {
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd >= 0) ::fchmod(fd, 0600), ::close(fd);  // an old temporary keeps its mode otherwise
  }
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    if (!file.flush()) {
      std::filesystem::remove(temporary, error);
      throw FileWriteError("cannot write '" + temporary +
                           "': check the folder exists, is writable and has free space");
    }
  }
  std::filesystem::rename(temporary, target, error);
  if (error) {
    std::filesystem::remove(temporary);
    throw FileWriteError("cannot rename '" + temporary + "' to '" + path + "' (" + error.message() +
                         ")");
  }
}

}  // namespace body_scan_driver
