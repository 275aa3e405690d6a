#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <relief/io/output.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <random>
#include <set>

namespace relief {

namespace fs = std::filesystem;

namespace {

// ---- signals: named temps being written are removed on a signal that can be caught
constexpr int kTempSlots = 64;
std::atomic<const char*> gTempFiles[kTempSlots];
constexpr int kCleanupSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM};

extern "C" void removeTempFilesAndRaise(int signal) {
    for (auto& slot : gTempFiles)
        if (const char* path = slot.load()) ::unlink(path);
    ::signal(signal, SIG_DFL);
    ::raise(signal);
}

void installSignalCleanup() {
    static const bool installed = [] {
        for (int signal : kCleanupSignals) {
            struct sigaction action {
            }, old{};
            action.sa_handler = removeTempFilesAndRaise;
            sigemptyset(&action.sa_mask);
            sigaction(signal, &action, &old);
            // A signal the caller ignores (nohup's SIGHUP) or handles stays theirs.
            if (old.sa_handler != SIG_DFL) sigaction(signal, &old, nullptr);
        }
        return true;
    }();
    (void)installed;
}

std::atomic<const char*>* registerTemp(const char* path) {
    installSignalCleanup();
    for (auto& slot : gTempFiles) {
        const char* expected = nullptr;
        if (slot.compare_exchange_strong(expected, path)) return &slot;
    }
    return nullptr;
}

// ---- low-level writes
std::mutex gHookMutex;
WriteFaultHook gHook;

int injectedFault(const std::string& path) {
    std::lock_guard lock(gHookMutex);
    return gHook ? gHook(path) : 0;
}

Error ioError(const std::string& path, const std::string& what, int error) {
    return makeError(ErrorKind::Io, "{}: {}: {}", path, what, std::strerror(error));
}

// SIGPIPE blocked while writing to a stream, so a reader that closed early is EPIPE (an error
// with the path) and not the end of the process.
class SigpipeBlock {
  public:
    SigpipeBlock() {
        sigemptyset(&m_pipe);
        sigaddset(&m_pipe, SIGPIPE);
        pthread_sigmask(SIG_BLOCK, &m_pipe, &m_old);
    }
    ~SigpipeBlock() {
        sigset_t pending;
        sigpending(&pending);
        if (sigismember(&pending, SIGPIPE) && !sigismember(&m_old, SIGPIPE)) {
            const timespec zero{};
            sigtimedwait(&m_pipe, nullptr, &zero);
        }
        pthread_sigmask(SIG_SETMASK, &m_old, nullptr);
    }

  private:
    sigset_t m_pipe, m_old;
};

Status writeAll(int fd, const char* data, size_t size, const std::string& path) {
    while (size > 0) {
        if (const int fault = injectedFault(path)) return ioError(path, "write failed", fault);
        const ssize_t n = ::write(fd, data, std::min<size_t>(size, size_t(1) << 20));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return ioError(path, "write failed", errno);
        if (n == 0) return makeError(ErrorKind::Io, "{}: write failed: no progress", path);
        data += n;
        size -= size_t(n);
    }
    return {};
}

std::string folderOf(const std::string& path) {
    const fs::path parent = fs::path(path).parent_path();
    return parent.empty() ? std::string(".") : parent.string();
}

std::string randomName() {
    static std::mutex mutex;
    static std::mt19937_64 engine{std::random_device{}() ^ (uint64_t(::getpid()) << 32)};
    std::lock_guard lock(mutex);
    char name[32];
    std::snprintf(name, sizeof name, "%016llx", (unsigned long long)engine());
    return std::string(kTempPrefix) + name;
}

bool isTempName(const char* name) {
    const size_t prefix = kTempPrefix.size();
    if (std::strncmp(name, kTempPrefix.data(), prefix) != 0 || std::strlen(name) != prefix + 16)
        return false;
    for (const char* c = name + prefix; *c; ++c)
        if (!std::isxdigit(static_cast<unsigned char>(*c))) return false;
    return true;
}

void cleanFolderOnce(const std::string& folder) {
    static std::mutex mutex;
    static std::set<std::string> cleaned;
    {
        std::lock_guard lock(mutex);
        if (!cleaned.insert(folder).second) return;
    }
    removeStaleTempFiles(folder);
}

mode_t processUmask() {
    // Read once: umask() can only be read by setting it.
    static const mode_t mask = [] {
        const mode_t m = ::umask(022);
        ::umask(m);
        return m;
    }();
    return mask;
}

std::string procPath(int fd) { return "/proc/self/fd/" + std::to_string(fd); }

enum class Kind { Replace, Stream, Stdout };

struct Target {
    Kind kind = Kind::Replace;
    std::string path;  // resolved: a symlink's target
    bool exists = false;
    struct stat st {};
};

// What is at `path`, following symlinks (a dangling one names the file to create).
Result<Target> classify(const std::string& path) {
    Target t;
    if (path == "-") {
        t.kind = Kind::Stdout;
        t.path = "-";
        return t;
    }
    if (path.empty()) return makeError(ErrorKind::BadArgument, "empty output path");
    std::string p = path;
    for (int hop = 0; hop < 40; ++hop) {
        if (::lstat(p.c_str(), &t.st) != 0) {
            if (errno != ENOENT && errno != ENOTDIR) return ioError(path, "cannot inspect", errno);
            const std::string folder = folderOf(p);
            struct stat fst {};
            if (::stat(folder.c_str(), &fst) != 0 || !S_ISDIR(fst.st_mode))
                return makeError(ErrorKind::Io, "{}: folder '{}' does not exist", path, folder);
            t.path = p;
            return t;
        }
        if (S_ISLNK(t.st.st_mode)) {
            std::string link(4096, '\0');
            const ssize_t n = ::readlink(p.c_str(), link.data(), link.size());
            if (n < 0) return ioError(path, "cannot read symbolic link", errno);
            link.resize(size_t(n));
            p = fs::path(link).is_absolute() ? link : (fs::path(folderOf(p)) / link).string();
            continue;
        }
        t.exists = true;
        t.path = p;
        const mode_t type = t.st.st_mode & S_IFMT;
        if (type == S_IFREG) return t;
        if (type == S_IFCHR || type == S_IFIFO) {
            t.kind = Kind::Stream;
            return t;
        }
        const char* what = type == S_IFDIR    ? "is a directory"
                           : type == S_IFSOCK ? "is a socket"
                           : type == S_IFBLK  ? "is a block device"
                                              : "is not a regular file";
        return makeError(ErrorKind::Io,
                         "{}: {}; relief writes regular files, character devices, FIFOs and '-' "
                         "(stdout)",
                         path, what);
    }
    return makeError(ErrorKind::Io, "{}: too many levels of symbolic links", path);
}

// "a.png", "./a.png" and "sub/../a.png" are one place (for files that do not exist yet).
bool samePlace(const std::string& a, const std::string& b) {
    std::error_code ec;
    return fs::absolute(a, ec).lexically_normal() == fs::absolute(b, ec).lexically_normal();
}

}  // namespace

struct OutputSet::Entry {
    std::string path;  // as given, for messages
    Target target;
    int fd = -1;
    bool anonymous = false;
    std::string tempName;  // a named temp on disk, removed unless renamed
    std::atomic<const char*>* slot = nullptr;

    void setTempName(std::string name) {
        forgetTempName();
        tempName = std::move(name);
        slot = registerTemp(tempName.c_str());
    }
    void forgetTempName() {
        if (slot) slot->store(nullptr);
        slot = nullptr;
        tempName.clear();
    }
    ~Entry() {
        if (!tempName.empty()) ::unlink(tempName.c_str());
        forgetTempName();
        if (fd >= 0) ::close(fd);
    }
};

namespace {

// A named temp in `folder`, created exclusively and held under flock for as long as it lives.
Status createNamedTemp(OutputSet::Entry& e, const std::string& folder, mode_t mode) {
    for (int attempt = 0; attempt < 100; ++attempt) {
        const std::string name = (fs::path(folder) / randomName()).string();
        const int fd =
            ::open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, mode);
        if (fd < 0 && errno == EEXIST) continue;
        if (fd < 0) return ioError(e.path, "cannot create a temp file in '" + folder + "'", errno);
        e.fd = fd;
        e.setTempName(name);
        struct stat mine {
        }, there{};
        // A cleaner in another process may have taken it between open and flock: start again.
        if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &mine) == 0 &&
            ::stat(name.c_str(), &there) == 0 && mine.st_ino == there.st_ino &&
            mine.st_dev == there.st_dev)
            return {};
        e.forgetTempName();
        ::close(fd);
        e.fd = -1;
    }
    return makeError(ErrorKind::Io, "{}: cannot create a temp file in '{}'", e.path, folder);
}

std::atomic<bool> gAnonymousTemps{true};

Status createTemp(OutputSet::Entry& e, const std::string& folder, mode_t mode) {
    cleanFolderOnce(folder);
#ifdef O_TMPFILE
    const int fd =
        gAnonymousTemps ? ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, mode) : -1;
    if (fd >= 0) {
        if (::access(procPath(fd).c_str(), W_OK) == 0) {
            ::flock(fd, LOCK_EX);
            e.fd = fd;
            e.anonymous = true;
            return {};
        }
        ::close(fd);  // no /proc to hand its path to a writer: a named temp instead
    }
#endif
    return createNamedTemp(e, folder, mode);
}

Status streamTo(const OutputSet::Entry& e) {
    int out = STDOUT_FILENO;
    if (e.target.kind == Kind::Stdout) {
        if (Status flushed = flushStdout(); !flushed) return flushed;
    } else {
        out = ::open(e.target.path.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
        if (out < 0) return ioError(e.path, "cannot open for writing", errno);
    }
    const SigpipeBlock block;
    Status status;
    std::vector<char> buffer(size_t(1) << 20);
    for (off_t offset = 0; status;) {
        const ssize_t n = ::pread(e.fd, buffer.data(), buffer.size(), offset);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) status = ioError(e.path, "cannot read back its temp file", errno);
        if (n <= 0) break;
        status = writeAll(out, buffer.data(), size_t(n), e.path);
        offset += n;
    }
    if (out != STDOUT_FILENO && ::close(out) != 0 && status)
        status = ioError(e.path, "write failed", errno);
    return status;
}

Status renameIntoPlace(OutputSet::Entry& e) {
    if (e.anonymous) {
        // linkat cannot replace a file: link to a fresh name, then rename that over the target.
        const std::string folder = folderOf(e.target.path);
        for (int attempt = 0;; ++attempt) {
            const std::string name = (fs::path(folder) / randomName()).string();
            if (::linkat(AT_FDCWD, procPath(e.fd).c_str(), AT_FDCWD, name.c_str(),
                         AT_SYMLINK_FOLLOW) == 0) {
                e.setTempName(name);
                break;
            }
            if (errno != EEXIST || attempt > 100)
                return ioError(e.path, "cannot link its temp file", errno);
        }
    }
    if (::rename(e.tempName.c_str(), e.target.path.c_str()) != 0)
        return ioError(e.path, "cannot rename into place", errno);
    e.forgetTempName();
    return {};
}

}  // namespace

OutputSet::OutputSet() = default;
OutputSet::~OutputSet() = default;

Status OutputSet::add(const std::string& path,
                      const std::function<Status(const std::string& tempPath)>& write) {
    Status status = [&]() -> Status {
        auto target = classify(path);
        if (!target) return target.error();
        for (const auto& other : m_entries) {
            const Target& o = other->target;
            // Two files at one place would race; one device (/dev/null twice) is fine.
            const bool same =
                target->kind != o.kind || target->kind == Kind::Stream ? false
                : target->kind == Kind::Stdout
                    ? true
                    : samePlace(o.path, target->path) ||
                          (target->exists && o.exists && o.st.st_ino == target->st.st_ino &&
                           o.st.st_dev == target->st.st_dev);
            if (same)
                return makeError(ErrorKind::BadArgument, "{}: given for two outputs of one command",
                                 path);
        }
        auto e = std::make_unique<Entry>();
        e->path = path == "-" ? std::string("stdout") : path;
        e->target = *target;
        const bool replace = target->kind == Kind::Replace;
        const std::string folder =
            replace ? folderOf(target->path) : fs::temp_directory_path().string();
        // Written as 0600 (a read-only old file must not stop the writer), given its mode after.
        if (Status made = createTemp(*e, folder, 0600); !made) return made;
        const std::string writePath = e->anonymous ? procPath(e->fd) : e->tempName;
        if (Status written = write(writePath); !written) return written;
        if (const int fault = injectedFault(e->path))
            return ioError(e->path, "write failed", fault);
        if (replace && target->exists) {
            // Keep the owner where allowed (root), then the mode (fchown may clear set-id bits).
            if (::fchown(e->fd, target->st.st_uid, target->st.st_gid) != 0) { /* not ours to give */
            }
        }
        const mode_t mode =
            target->exists ? (target->st.st_mode & 07777) : (0666 & ~processUmask());
        if (replace && ::fchmod(e->fd, mode) != 0)
            return ioError(e->path, "cannot set the mode of its temp file", errno);
        if (replace && ::fsync(e->fd) != 0) return ioError(e->path, "write failed", errno);
        m_entries.push_back(std::move(e));
        return {};
    }();
    if (!status) m_failed = true;
    return status;
}

Status OutputSet::addText(const std::string& path, std::string_view text) {
    return add(path, [&](const std::string& temp) -> Status {
        const int fd = ::open(temp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
        if (fd < 0) return ioError(path, "cannot open for writing", errno);
        Status status = writeAll(fd, text.data(), text.size(), path == "-" ? "stdout" : path);
        if (::close(fd) != 0 && status) status = ioError(path, "write failed", errno);
        return status;
    });
}

Status OutputSet::commit() {
    if (m_failed || m_committed)
        return makeError(ErrorKind::Io, "outputs not written: {}",
                         m_failed ? "one of them failed" : "already committed");
    m_committed = true;
    // Streams first: they cannot be taken back, and a failed one leaves every file untouched.
    for (auto& e : m_entries)
        if (e->target.kind != Kind::Replace)
            if (Status s = streamTo(*e); !s) return s;
    for (auto& e : m_entries)
        if (e->target.kind == Kind::Replace)
            if (Status s = renameIntoPlace(*e); !s) return s;
    m_entries.clear();
    return {};
}

bool hasExtension(std::string_view path, std::string_view ext) {
    return path.size() >= ext.size() &&
           std::equal(
               ext.begin(), ext.end(), path.end() - std::ptrdiff_t(ext.size()),
               [](char e, char p) { return e == std::tolower(static_cast<unsigned char>(p)); });
}

void setAnonymousTempsForTesting(bool allowed) { gAnonymousTemps = allowed; }

void setWriteFaultHookForTesting(WriteFaultHook hook) {
    std::lock_guard lock(gHookMutex);
    gHook = std::move(hook);
}

Status flushStdout() {
    const SigpipeBlock block;
    // std::cout flushes stdout itself (it is synced with stdio): keep the first errno.
    errno = 0;
    std::cout.flush();
    int error = errno;
    const bool flushed = std::fflush(stdout) == 0;
    if (error == 0) error = errno;
    const bool bad = !flushed || std::ferror(stdout) || !std::cout;
    if (!bad) return {};
    std::clearerr(stdout);
    std::cout.clear();
    if (error != 0) return ioError("stdout", "write failed", error);
    return makeError(ErrorKind::Io, "stdout: write failed");
}

int removeStaleTempFiles(const std::string& folder) {
    DIR* dir = ::opendir(folder.c_str());
    if (!dir) return 0;
    int removed = 0;
    while (const dirent* entry = ::readdir(dir)) {
        if (!isTempName(entry->d_name)) continue;
        const std::string name = (fs::path(folder) / entry->d_name).string();
        const int fd = ::open(name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
        if (fd < 0) continue;
        struct stat mine {
        }, there{};
        // The lock is free only when the process that made the file is gone.
        if (::fstat(fd, &mine) == 0 && S_ISREG(mine.st_mode) &&
            ::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::stat(name.c_str(), &there) == 0 &&
            mine.st_ino == there.st_ino && ::unlink(name.c_str()) == 0)
            ++removed;
        ::close(fd);
    }
    ::closedir(dir);
    return removed;
}

}  // namespace relief
