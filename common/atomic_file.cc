#include "common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace aslam {
namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& what, int error) {
  throw std::runtime_error("cannot write " + path + ": " + what + ": " + std::strerror(error));
}

// fsync of a folder, so a rename in it survives a power cut.
int SyncFolder(const std::string& folder) {
  const int fd = open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int error = fsync(fd) == 0 ? 0 : errno;
  close(fd);
  return error;
}

}  // namespace

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  const std::filesystem::path target(path);
  if (!target.has_filename()) Fail(path, "not a file name", EISDIR);
  const std::string folder = target.has_parent_path() ? target.parent_path().string() : ".";
  // Hidden and in the same folder: rename is atomic only within one file system.
  std::string temp = folder + "/." + target.filename().string() + ".tmp.XXXXXX";
  const int fd = mkostemp(temp.data(), O_CLOEXEC);
  if (fd < 0) Fail(path, "cannot create a temporary file in " + folder, errno);
  auto give_up = [&](const std::string& what) {
    const int error = errno;
    close(fd);
    unlink(temp.c_str());
    Fail(path, what, error);
  };
  if (fchmod(fd, 0644) != 0) give_up("fchmod");
  std::size_t done = 0;
  while (done < contents.size()) {
    const ssize_t n = write(fd, contents.data() + done, contents.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) errno = ENOSPC;  // a regular file takes at least one byte or says why not
    if (n <= 0) give_up("write");
    done += static_cast<std::size_t>(n);
  }
  if (fsync(fd) != 0) give_up("fsync");
  if (close(fd) != 0) {
    const int error = errno;
    unlink(temp.c_str());
    Fail(path, "close", error);
  }
  if (rename(temp.c_str(), path.c_str()) != 0) {
    const int error = errno;
    unlink(temp.c_str());
    Fail(path, "rename", error);
  }
  if (const int error = SyncFolder(folder); error != 0) Fail(path, "fsync of " + folder, error);
}

}  // namespace aslam
