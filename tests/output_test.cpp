// The output mechanism (io/output.h): what is at the path decides how it is written, several
// outputs are one transaction, temp files never accumulate, every write error names the path.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <relief/io/image_write.h>
#include <relief/io/output.h>
#include <sys/file.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

namespace relief {
namespace {

namespace fs = std::filesystem;

class Output : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                (std::string("relief_output_") + test->name() + "_" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override {
        setWriteFaultHookForTesting(nullptr);
        setAnonymousTempsForTesting(true);
        fs::remove_all(m_dir);
    }
    std::string path(const std::string& name) const { return (m_dir / name).string(); }
    static std::string contents(const std::string& p) {
        std::ifstream in(p, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }
    // Names in the folder, to check that no temp file is left.
    std::vector<std::string> entries() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(m_dir))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    static bool mentions(const Status& s, const std::string& text) {
        return !s.ok() && s.error().message.find(text) != std::string::npos;
    }
    fs::path m_dir;
};

using Names = std::vector<std::string>;

TEST_F(Output, RegularFileIsReplacedAndKeepsItsMode) {
    for (mode_t mode : {0600, 0640, 0444}) {
        std::ofstream(path("a.txt")) << "old";
        ASSERT_EQ(::chmod(path("a.txt").c_str(), mode), 0);
        ASSERT_TRUE(writeTextFile(path("a.txt"), "new").ok());
        EXPECT_EQ(contents(path("a.txt")), "new");
        struct stat st {};
        ASSERT_EQ(::stat(path("a.txt").c_str(), &st), 0);
        EXPECT_EQ(st.st_mode & 07777, mode);
        EXPECT_EQ(entries(), Names{"a.txt"});
        fs::remove(path("a.txt"));
    }
}

TEST_F(Output, SymlinkIsFollowedAndItsTargetWritten) {
    fs::create_directories(m_dir / "real");
    std::ofstream(path("real/t.txt")) << "old";
    fs::create_symlink("real/t.txt", m_dir / "link.txt");
    fs::create_symlink("link.txt", m_dir / "link2.txt");  // a chain
    fs::create_symlink("real/new.txt", m_dir / "dangling.txt");
    ASSERT_TRUE(writeTextFile(path("link2.txt"), "new").ok());
    ASSERT_TRUE(writeTextFile(path("dangling.txt"), "made").ok());
    EXPECT_TRUE(fs::is_symlink(m_dir / "link.txt"));
    EXPECT_TRUE(fs::is_symlink(m_dir / "link2.txt"));
    EXPECT_TRUE(fs::is_symlink(m_dir / "dangling.txt"));
    EXPECT_EQ(contents(path("real/t.txt")), "new");
    EXPECT_EQ(contents(path("real/new.txt")), "made");
    fs::create_symlink("loop.txt", m_dir / "loop.txt");
    EXPECT_TRUE(mentions(writeTextFile(path("loop.txt"), "x"), "symbolic links"));
}

TEST_F(Output, FifoIsStreamedTo) {
    ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
    const std::string text(3 << 20, 'x');  // far more than a pipe holds
    std::string received;
    std::thread reader([&] { received = contents(path("f")); });
    const Status s = writeTextFile(path("f"), text);
    reader.join();
    EXPECT_TRUE(s.ok()) << s.error().message;
    EXPECT_EQ(received.size(), text.size());
    EXPECT_TRUE(fs::is_fifo(m_dir / "f"));
    EXPECT_EQ(entries(), Names{"f"});
}

TEST_F(Output, FifoWhoseReaderClosesEarlyIsBrokenPipe) {
    ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
    std::thread reader([&] {
        const int fd = ::open(path("f").c_str(), O_RDONLY);
        char some[16];
        (void)!::read(fd, some, sizeof some);
        ::close(fd);
    });
    const Status s = writeTextFile(path("f"), std::string(8 << 20, 'x'));
    reader.join();
    EXPECT_TRUE(mentions(s, path("f") + ": write failed: Broken pipe")) << s.error().message;
}

TEST_F(Output, DirectorySocketAndMissingFolderAreRefused) {
    fs::create_directories(m_dir / "d");
    const Status dir = writeTextFile(path("d"), "x");
    EXPECT_TRUE(mentions(dir, path("d") + ": is a directory")) << dir.error().message;
    EXPECT_TRUE(fs::is_directory(m_dir / "d"));

    const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string socketPath = path("s");
    ASSERT_LT(socketPath.size(), sizeof address.sun_path);
    std::strcpy(address.sun_path, socketPath.c_str());
    ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    EXPECT_TRUE(mentions(writeTextFile(socketPath, "x"), socketPath + ": is a socket"));
    ::close(sock);
    EXPECT_TRUE(fs::is_socket(m_dir / "s"));

    EXPECT_TRUE(mentions(writeTextFile(path("missing/x"), "x"), "does not exist"));
    EXPECT_TRUE(mentions(writeTextFile(path("d/../missing/x"), "x"), "does not exist"));
}

TEST_F(Output, SeveralOutputsAreOneTransaction) {
    std::ofstream(path("a.txt")) << "old a";
    std::ofstream(path("b.txt")) << "old b";
    fs::create_directories(m_dir / "d");
    // The third output fails in each way: a missing folder, a refused target, a failed writer.
    const auto failThird = [&](OutputSet& set) {
        ASSERT_TRUE(set.addText(path("a.txt"), "new a").ok());
        ASSERT_TRUE(set.addText(path("b.txt"), "new b").ok());
    };
    for (int way = 0; way < 3; ++way) {
        {
            OutputSet set;
            failThird(set);
            const Status third = way == 0 ? set.addText(path("missing/c.txt"), "c")
                                 : way == 1
                                     ? set.addText(path("d"), "c")
                                     : set.add(path("c.txt"), [](const std::string& temp) {
                                           std::ofstream(temp) << "half";
                                           return Status(makeError(ErrorKind::Io, "simulated"));
                                       });
            EXPECT_FALSE(third.ok());
            EXPECT_FALSE(set.commit().ok());  // a failed set writes nothing
        }
        EXPECT_EQ(contents(path("a.txt")), "old a");
        EXPECT_EQ(contents(path("b.txt")), "old b");
        EXPECT_EQ(entries(), (Names{"a.txt", "b.txt", "d"})) << "way " << way;
    }
    OutputSet set;
    failThird(set);
    EXPECT_EQ(contents(path("a.txt")), "old a") << "nothing is in place before commit";
    ASSERT_TRUE(set.commit().ok());
    EXPECT_EQ(contents(path("a.txt")), "new a");
    EXPECT_EQ(contents(path("b.txt")), "new b");
}

TEST_F(Output, OnePathTwiceInOneSetIsRefused) {
    OutputSet set;
    ASSERT_TRUE(set.addText(path("a.txt"), "1").ok());
    fs::create_symlink("a.txt", m_dir / "l.txt");
    EXPECT_TRUE(mentions(set.addText(path("a.txt"), "2"), "given for two outputs"));
    EXPECT_TRUE(mentions(set.addText(path("l.txt"), "2"), "given for two outputs"));
    ASSERT_TRUE(set.addText(path("new.txt"), "1").ok());
    fs::create_directories(m_dir / "d");
    EXPECT_TRUE(mentions(set.addText(path("d/../new.txt"), "2"), "given for two outputs"));
}

TEST_F(Output, FailedStreamLeavesTheFilesUntouched) {
    std::ofstream(path("a.txt")) << "old";
    ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
    std::thread reader([&] { ::close(::open(path("f").c_str(), O_RDONLY)); });
    {
        OutputSet set;
        ASSERT_TRUE(set.addText(path("a.txt"), "new").ok());
        ASSERT_TRUE(set.addText(path("f"), std::string(4 << 20, 'x')).ok());
        EXPECT_TRUE(mentions(set.commit(), "Broken pipe"));
    }
    reader.join();
    EXPECT_EQ(contents(path("a.txt")), "old");
    EXPECT_EQ(entries(), (Names{"a.txt", "f"}));
}

TEST_F(Output, FullDiskIsReportedWithThePath) {
    // An injected failure stands in for a full disk: no test writes to a system device.
    std::ofstream(path("a.txt")) << "old";
    std::ofstream(path("b.png")) << "old";
    setWriteFaultHookForTesting(
        [&](const std::string& p) { return p == path("b.png") ? ENOSPC : 0; });
    OutputSet set;
    ASSERT_TRUE(set.addText(path("a.txt"), "new").ok());
    const Status png = writePng(set, path("b.png"), ImageRgb8(4, 4));
    EXPECT_TRUE(mentions(png, path("b.png") + ": write failed: No space left on device"))
        << png.error().message;
    EXPECT_FALSE(set.commit().ok());
    setWriteFaultHookForTesting([](const std::string&) { return ENOSPC; });
    EXPECT_TRUE(mentions(writeTextFile(path("a.txt"), "new"), "No space left on device"));
    EXPECT_TRUE(mentions(writeExr(path("c.exr"), ImageF(2, 2)), "No space left on device"));
    EXPECT_EQ(contents(path("a.txt")), "old");
    EXPECT_EQ(contents(path("b.png")), "old");
    EXPECT_EQ(entries(), (Names{"a.txt", "b.png"}));
}

TEST_F(Output, LongestValidNameIsWritten) {
    const std::string name = std::string(NAME_MAX - 4, 'n') + ".png";
    ASSERT_TRUE(writePng(path(name), ImageRgb8(2, 2)).ok());
    EXPECT_TRUE(fs::is_regular_file(m_dir / name));
    EXPECT_EQ(entries(), Names{name});
}

TEST_F(Output, StaleTempFilesAreRemovedLiveOnesKept) {
    const std::string stale = path(std::string(kTempPrefix) + "0123456789abcdef");
    const std::string live = path(std::string(kTempPrefix) + "fedcba9876543210");
    const std::string other = path(std::string(kTempPrefix) + "not-ours");
    for (const std::string& p : {stale, live, other}) std::ofstream(p) << "x";
    // Held as a live writer holds its temp (flock is per open file, so this open counts as one).
    const int held = ::open(live.c_str(), O_RDONLY);
    ASSERT_EQ(::flock(held, LOCK_EX), 0);
    EXPECT_EQ(removeStaleTempFiles(m_dir.string()), 1);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(live));
    EXPECT_TRUE(fs::exists(other));
    ::close(held);
    // The first output into a folder cleans it.
    std::ofstream(stale) << "x";
    ASSERT_TRUE(writeTextFile(path("a.txt"), "a").ok());
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_FALSE(fs::exists(live));
}

TEST_F(Output, KilledWriterLeavesNothingTheNextRunKeeps) {
    for (const bool anonymous : {true, false}) {
        SCOPED_TRACE(anonymous ? "anonymous temps" : "named temps");
        std::ofstream(path("a.txt")) << "old";
        const pid_t child = fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            setAnonymousTempsForTesting(anonymous);
            (void)writeAtomically(path("a.txt"), [](const std::string& temp) -> Status {
                std::ofstream(temp) << "half";
                ::raise(SIGKILL);  // cannot be caught: no cleanup runs
                return {};
            });
            _exit(0);
        }
        int status = 0;
        waitpid(child, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status));
        EXPECT_EQ(contents(path("a.txt")), "old");
        EXPECT_EQ(entries().size(), anonymous ? 1u : 2u) << "a named temp stays until the next run";
        // The next output into the folder (this process's first there) removes it.
        const std::string next = path("sub" + std::to_string(anonymous));
        fs::create_directories(next);
        fs::rename(path("a.txt"), next + "/a.txt");
        for (const auto& e : fs::directory_iterator(m_dir))
            if (e.path().filename().string().rfind(kTempPrefix, 0) == 0)
                fs::rename(e.path(), next / e.path().filename());
        ASSERT_TRUE(writeTextFile(next + "/b.txt", "b").ok());
        EXPECT_EQ(std::distance(fs::directory_iterator(next), fs::directory_iterator()), 2);
        fs::remove_all(next);
    }
}

TEST_F(Output, NamedTempsWorkAndLeaveNothing) {
    setAnonymousTempsForTesting(false);
    std::ofstream(path("a.txt")) << "old";
    ::chmod(path("a.txt").c_str(), 0600);
    {
        OutputSet set;
        ASSERT_TRUE(set.addText(path("a.txt"), "new").ok());
        ASSERT_TRUE(
            writePng(set, path(std::string(NAME_MAX - 4, 'n') + ".png"), ImageRgb8(2, 2)).ok());
        EXPECT_EQ(entries().size(), 3u) << "two named temps and the old file";
        ASSERT_TRUE(set.commit().ok());
    }
    {
        OutputSet set;
        ASSERT_TRUE(set.addText(path("a.txt"), "newer").ok());
        EXPECT_FALSE(set.addText(path("missing/b.txt"), "b").ok());
    }
    setAnonymousTempsForTesting(true);
    EXPECT_EQ(contents(path("a.txt")), "new");
    EXPECT_EQ(fs::status(path("a.txt")).permissions(), fs::perms(0600));
    EXPECT_EQ(entries(), (Names{"a.txt", std::string(NAME_MAX - 4, 'n') + ".png"}));
}

TEST_F(Output, DevicesAreStreamedNotReplaced) {
    // A character device of our own making is out of reach without privileges; a FIFO behind a
    // symlink takes the same path (followed, then streamed).
    ASSERT_EQ(::mkfifo(path("f").c_str(), 0600), 0);
    fs::create_symlink("f", m_dir / "l");
    std::string received;
    std::thread reader([&] { received = contents(path("f")); });
    EXPECT_TRUE(writeTextFile(path("l"), "through the link").ok());
    reader.join();
    EXPECT_EQ(received, "through the link");
    EXPECT_TRUE(fs::is_symlink(m_dir / "l"));
}

}  // namespace
}  // namespace relief
