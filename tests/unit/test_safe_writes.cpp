// Files written by a temporary beside them, renamed into place (issue 43, item 3): a symbolic
// link planted at the temporary names a writer could be expected to use (the old
// ".NAME.tmp-PID", the checkpoints' "NAME.partial") is never followed, whatever writes: a
// whole file (write_bytes: vector documents, serve's saves), a streamed image, a checkpoint.
#include <fixpoint/host/core/checkpoint.hpp>
#include <fixpoint/host/core/image_io.hpp>

#include "cli.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

using namespace fp::test;

namespace {

namespace fs = std::filesystem;

/// A folder with a victim file outside the target's folder and links to it at every name a
/// writer of `name` could have been expected to use. Returns the victim's path.
std::string plant(const std::string& dir, const std::string& name) {
    fs::create_directories(dir + "/out");
    const std::string victim = dir + "/victim.txt";
    write_file(victim, "precious");
    const std::string pid = std::to_string(::getpid());
    for (const std::string& t :
         {"." + name + ".tmp-" + pid, name + ".partial", "." + name + ".partial-" + pid})
        fs::create_symlink(victim, dir + "/out/" + t);
    return victim;
}

/// The names in `dir` that are not the planted links nor `keep`.
std::set<std::string> others(const std::string& dir, const std::string& keep) {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir))
        if (!fs::is_symlink(e.symlink_status()) && e.path().filename() != keep)
            names.insert(e.path().filename().string());
    return names;
}

TEST(SafeWrites, WriteBytesNeverFollowsALinkAtATemporaryName) {
    const std::string dir = scratch_dir("safe-writes-bytes");
    const std::string victim = plant(dir, "doc.svg");
    fp::host::write_bytes(std::string("<svg/>"), dir + "/out/doc.svg");
    EXPECT_EQ(read_file(victim), "precious");
    EXPECT_EQ(read_file(dir + "/out/doc.svg"), "<svg/>");
    EXPECT_TRUE(others(dir + "/out", "doc.svg").empty());
}

TEST(SafeWrites, AStreamedImageNeverFollowsALinkAtATemporaryName) {
    const std::string dir = scratch_dir("safe-writes-stream");
    const std::string victim = plant(dir, "img.png");
    {
        fp::host::StreamedImage s(dir + "/out/img.png", 4, 2, 8, "recipe", {}, fp::host::Tiled::No);
        // Its temporary is a new file of its own, not a link.
        EXPECT_FALSE(fs::is_symlink(fs::symlink_status(s.temporary_path())));
        const std::vector<float> rows(4 * 2 * 3, 0.5f);
        s.rows(0, 2, rows.data());
        s.finish();
    }
    EXPECT_EQ(read_file(victim), "precious");
    EXPECT_GT(fs::file_size(dir + "/out/img.png"), 8u);
    EXPECT_TRUE(others(dir + "/out", "img.png").empty());
}

TEST(SafeWrites, ACheckpointNeverFollowsALinkAtATemporaryName) {
    const std::string dir = scratch_dir("safe-writes-checkpoint");
    const std::string victim = plant(dir, "ck.bin");
    fp::host::CheckpointHeader h{"0.1.0", "chaos-game", "identity", 10};
    fp::host::write_checkpoint_file(dir + "/out/ck.bin", h,
                                    [](fp::CheckpointSink& s) { s.write("payload", 7); });
    EXPECT_EQ(read_file(victim), "precious");
    const fp::host::CheckpointFile back(dir + "/out/ck.bin");
    EXPECT_EQ(back.header().identity, "identity");
    EXPECT_TRUE(others(dir + "/out", "ck.bin").empty());
}

TEST(SafeWrites, TemporaryNamesAreUniqueAndNew) {
    const std::string dir = scratch_dir("safe-writes-names");
    std::set<std::string> seen;
    std::vector<int> fds;
    for (int i = 0; i < 32; ++i) {
        fs::path tmp;
        const int fd = fp::host::open_temp_beside(fs::path(dir) / "a.png", tmp);
        ASSERT_GE(fd, 0);
        fds.push_back(fd);
        EXPECT_EQ(tmp.parent_path(), fs::path(dir));
        EXPECT_EQ(tmp.filename().string().rfind(".a.png.tmp-" + std::to_string(::getpid()) + "-", 0), 0u)
            << tmp;
        EXPECT_TRUE(seen.insert(tmp.string()).second) << tmp;
    }
    for (const int fd : fds) ::close(fd);
    for (const auto& s : seen) fs::remove(s);
}

} // namespace
