// Every output of every command on a full disk and in a read-only folder: a clear message naming the file,
// a non-zero exit, the file that was there untouched, and no temporary file left behind. Each case runs
// in a mount namespace of its own (unshare, as an ordinary user too where user namespaces are allowed) on
// a 64 kB tmpfs: filled to the last byte, or remounted read-only, which holds even for root.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using hapticut::test::slurp;

enum class Place { FullDisk, ReadOnlyFolder };

struct Confined {
    int exitCode = -1;
    std::string err, existingAfter, listing;
};

/// Runs hapticut with `args`, where {T} names the tmpfs, after putting "old contents" into {T}/`existing`.
Confined runConfined(const fs::path& scratch, Place place, const std::string& args, const std::string& existing) {
    std::string command = args;
    for (std::size_t at; (at = command.find("{T}")) != std::string::npos;) command.replace(at, 3, "\"$T\"");
    const std::string s = scratch.string();
    const std::string script = "T=" + s +
                               "/mnt; mkdir -p \"$T\"; mount -t tmpfs -o size=64k tmpfs \"$T\" || exit 97; "
                               "printf \"old contents\\n\" > \"$T/" +
                               existing + "\"; " +
                               (place == Place::FullDisk ? "dd if=/dev/zero of=\"$T/filler\" bs=4k 2>/dev/null; "
                                                         : "mount -o remount,ro \"$T\" || exit 97; ") +
                               HAPTICUT_EXE + " " + command + " >" + s + "/out 2>" + s + "/err; echo $? >" + s +
                               "/code; " + "cat \"$T/" + existing + "\" >" + s + "/after; ls -A \"$T\" >" + s +
                               "/listing";
    const std::string shell = "unshare --mount --map-root-user sh -c '" + script + "' 2>" + s + "/unshare-err";
    const int status = std::system(shell.c_str());
    Confined r;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return r;  // no namespace here: exitCode stays -1
    r.exitCode = std::stoi(slurp(scratch / "code"));
    r.err = slurp(scratch / "err");
    r.existingAfter = slurp(scratch / "after");
    r.listing = slurp(scratch / "listing");
    return r;
}

TEST(ConfinedOutputs, EveryOutputOnAFullDiskOrAReadOnlyFolderFailsClearlyAndKeepsTheOldFile) {
    const std::string press = std::string(HAPTICUT_SOURCE_DIR) + "/assets/trajectories/press-front.csv";
    const struct {
        std::string args, file;
    } outputs[] = {
        {"run --steps 20 --report {T}/r.json", "r.json"},
        {"run --steps 20 --export-mesh {T}/m.obj", "m.obj"},
        {"run --trajectory " + press + " --steps 50 --report {T}/r.json", "r.json"},
        {"run --trajectory " + press + " --steps 50 --force-log {T}/f.csv", "f.csv"},
        {"run --trajectory " + press + " --steps 50 --record {T}/rec.csv", "rec.csv"},
        {"run --trajectory " + press + " --steps 50 --export-mesh {T}/m.ply", "m.ply"},
        {"soak --strokes 3 --report {T}/s.json", "s.json"},
        {"convert heart {T}/h.obj", "h.obj"},
        {"convert heart {T}/h.ply", "h.ply"},
        {"convert heart {T}/h.txt", "h.txt"},
        {"bench --triangles 1619 --integrators euler --seconds 0.01 --json {T}/b.json", "b.json"},
    };
    for (const Place place : {Place::FullDisk, Place::ReadOnlyFolder}) {
        for (const auto& o : outputs) {
            const std::string what = (place == Place::FullDisk ? "full disk: " : "read-only folder: ") + o.args;
            SCOPED_TRACE(what);
            hapticut::test::ScratchDir dir;
            const Confined r = runConfined(dir.path(), place, o.args, o.file);
            if (r.exitCode == -1) GTEST_SKIP() << "no mount namespace for a tmpfs here: " << slurp(dir / "unshare-err");
            EXPECT_NE(r.exitCode, 0) << r.err;
            EXPECT_NE(r.exitCode, 128 + 6) << "aborted:\n" << r.err;
            EXPECT_NE(r.err.find(o.file), std::string::npos) << "the message names the file:\n" << r.err;
            EXPECT_NE(r.err.find(place == Place::FullDisk ? "No space left on device" : "Read-only file system"),
                      std::string::npos)
                << "and says why:\n"
                << r.err;
            EXPECT_EQ(r.existingAfter, "old contents\n") << "the file that was there is untouched";
            EXPECT_EQ(r.listing.find(".tmp"), std::string::npos) << "no temporary file left:\n" << r.listing;
        }
    }
}

}  // namespace
