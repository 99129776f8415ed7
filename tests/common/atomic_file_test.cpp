// Files written atomically: a write that fails, is abandoned, or is ended by a signal leaves the target
// as it was and nothing beside it; the errors say what went wrong with which file.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <fstream>

#include "hapticut/common/temp_files.h"
#include "hapticut/common/text_file.h"
#include "test_support.h"

namespace hapticut {
namespace {

namespace fs = std::filesystem;

using test::slurp;

TEST(AtomicFile, ReplacesTheTargetOnlyWhenCommitted) {
    test::ScratchDir dir;
    std::ofstream(dir / "log.csv") << "before\n";
    {
        auto file = AtomicFile::create(dir / "log.csv");
        ASSERT_TRUE(file) << file.error().toString();
        EXPECT_TRUE(file->write("t,x\n"));
        EXPECT_TRUE(file->write("0,1\n"));
        EXPECT_TRUE(fs::exists(dir / "log.csv.tmp-hapticut"));
        EXPECT_EQ(slurp(dir / "log.csv"), "before\n") << "untouched while written";
        EXPECT_FALSE(file->commit());
    }
    EXPECT_EQ(slurp(dir / "log.csv"), "t,x\n0,1\n");
    EXPECT_FALSE(fs::exists(dir / "log.csv.tmp-hapticut"));
}

TEST(AtomicFile, AnAbandonedWriteLeavesTheTargetAndNoTemporaryFile) {
    test::ScratchDir dir;
    std::ofstream(dir / "log.csv") << "before\n";
    {
        auto file = AtomicFile::create(dir / "log.csv");
        ASSERT_TRUE(file);
        file->write("half a ro");
    }  // destroyed without commit: a run that failed
    EXPECT_EQ(slurp(dir / "log.csv"), "before\n");
    EXPECT_FALSE(fs::exists(dir / "log.csv.tmp-hapticut"));
}

TEST(AtomicFile, AStaleTemporaryFileOfAKilledProcessIsReplacedByTheNextWrite) {
    test::ScratchDir dir;
    std::ofstream(dir / "out.ply.tmp-hapticut") << std::string(100'000, 'x');
    ASSERT_FALSE(writeTextFileAtomically(dir / "out.ply", "ply\n"));
    EXPECT_EQ(slurp(dir / "out.ply"), "ply\n");
    EXPECT_FALSE(fs::exists(dir / "out.ply.tmp-hapticut"));
}

TEST(AtomicFile, AFolderOrAnUnwritablePlaceIsRefusedWithTheReason) {
    test::ScratchDir dir;
    fs::create_directory(dir / "folder");
    const WriteStatus folder = writeTextFileAtomically(dir / "folder", "x");
    ASSERT_TRUE(folder);
    EXPECT_EQ(folder->file, dir / "folder");
    EXPECT_NE(folder->message.find("is a folder, expected a file"), std::string::npos) << folder->toString();
    EXPECT_EQ(folder->message.find("Success"), std::string::npos) << folder->toString();

    const WriteStatus missing = writeTextFileAtomically(dir / "nowhere" / "x.csv", "x");
    ASSERT_TRUE(missing);
    EXPECT_NE(missing->message.find("No such file or directory"), std::string::npos) << missing->toString();
}

TEST(AtomicFile, AFullDiskFailsTheCommitAndKeepsTheTarget) {
    // /dev/full takes the place of a full disk: every write to it fails with ENOSPC.
    if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
    test::ScratchDir dir;
    std::ofstream(dir / "log.csv") << "before\n";
    fs::create_symlink("/dev/full", dir / "log.csv.tmp-hapticut");
    auto file = AtomicFile::create(dir / "log.csv");
    ASSERT_TRUE(file);
    file->write(std::string(1 << 20, 'x'));
    const WriteStatus error = file->commit();
    ASSERT_TRUE(error);
    EXPECT_NE(error->message.find("No space left on device"), std::string::npos) << error->toString();
    EXPECT_EQ(slurp(dir / "log.csv"), "before\n");
}

// A process ended by SIGTERM or SIGINT while it writes (here a child that raises the signal mid-write)
// leaves no temporary file and the target as it was, and dies of that signal.
TEST(AtomicFile, ASignalMidWriteRemovesTheTemporaryFile) {
    for (const int number : {SIGTERM, SIGINT, SIGHUP}) {
        test::ScratchDir dir;
        std::ofstream(dir / "model.ply") << "before\n";
        const pid_t child = ::fork();
        if (child == 0) {
            removeTempFilesOnSignals();
            auto file = AtomicFile::create(dir / "model.ply");
            if (!file) ::_exit(2);
            file->write(std::string(100'000, 'x'));
            std::raise(number);
            ::_exit(3);  // not reached: the signal ends the process
        }
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        ASSERT_TRUE(WIFSIGNALED(status)) << "exit " << WEXITSTATUS(status);
        EXPECT_EQ(WTERMSIG(status), number);
        EXPECT_FALSE(fs::exists(dir / "model.ply.tmp-hapticut")) << "signal " << number;
        EXPECT_EQ(slurp(dir / "model.ply"), "before\n");
    }
}

}  // namespace
}  // namespace hapticut
