// Outputs are written to a temp file and renamed: an error or a signal mid-write leaves the
// previous file untouched and no temp file behind.
#include <relief/io/image_write.h>

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

namespace relief {
namespace {

namespace fs = std::filesystem;

fs::path freshFolder(const char* name) {
    const fs::path dir = fs::temp_directory_path() / (std::string("relief_atomic_") + name + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string contents(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(AtomicWrite, FailedWriteKeepsOldFileAndLeavesNoTemp) {
    const fs::path dir = freshFolder("fail");
    ASSERT_TRUE(writeTextFile((dir / "out.txt").string(), "old").ok());
    const Status s = writeAtomically((dir / "out.txt").string(), [](const std::string& temp) -> Status {
        std::ofstream(temp) << "half";
        return makeError(ErrorKind::Io, "simulated failure");
    });
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(contents(dir / "out.txt"), "old");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
    fs::remove_all(dir);
}

TEST(AtomicWrite, SignalDuringWriteLeavesNoPartialOutput) {
    for (const bool anonymous : {true, false})  // named temps: a filesystem without O_TMPFILE
    for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2}) {
        const fs::path dir = freshFolder("signal");
        ASSERT_TRUE(writeTextFile((dir / "out.txt").string(), "old").ok());
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            const rlimit noCore{0, 0};  // SIGQUIT would dump core into the working folder
            setrlimit(RLIMIT_CORE, &noCore);
            setAnonymousTempsForTesting(anonymous);
            (void)writeAtomically((dir / "out.txt").string(), [signal](const std::string& temp) -> Status {
                std::ofstream(temp) << "half written";
                ::raise(signal);
                return {};
            });
            _exit(0);  // not reached: the signal ends the process
        }
        int status = 0;
        waitpid(child, &status, 0);
        EXPECT_TRUE(WIFSIGNALED(status)) << "signal " << signal << (anonymous ? "" : " (named)");
        EXPECT_EQ(contents(dir / "out.txt"), "old");
        EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1)
            << "a temp file was left behind";
        fs::remove_all(dir);
    }
}

TEST(AtomicWrite, MissingFolderIsAClearError) {
    const Status s = writeTextFile("/nonexistent-relief-folder/x.txt", "x");
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.error().message.find("does not exist"), std::string::npos);
}

}  // namespace
}  // namespace relief
