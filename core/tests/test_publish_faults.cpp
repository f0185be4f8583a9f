// Publishing outputs under faults (PublishFaults): a full disk during every writer, under a file
// size limit (always) and on a real tmpfs (where mount is permitted); earlier outputs intact.
#include "publish_checks.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <cstdlib>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/statvfs.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using namespace npf::testing::publish;

// Item 2 of issue 17 under a file size limit (EFBIG, as a full disk gives ENOSPC): each writer
// fails with one line naming its file, and the earlier output is intact.
TEST(PublishFaults, FileSizeLimitKeepsEveryEarlierOutput) {
    const std::string dir = npf::testing::temporary_folder("publish-faults");
    for (const Writer& w : writers()) {
        const std::string out = dir + "/" + w.command + "-" + w.file;
        ASSERT_EQ(npf::testing::run_tool(w.args(out)).status, 0) << w.command;
        const std::string earlier = read_text(out);
        ASSERT_GT(earlier.size(), 2048u) << w.command << ": the output must outgrow the 1 KiB limit";
        const ToolRun r = run_limited(w.args(out));
        expect_one_line_error(r, w.command, out, std::strerror(EFBIG));
        EXPECT_TRUE(read_text(out) == earlier) << w.command << " changed the earlier output";
    }
    // render --png: both earlier files stay.
    const std::string exr = dir + "/both.exr", png = dir + "/both.png";
    ASSERT_EQ(npf::testing::run_tool(render_png_args(exr, png)).status, 0);
    const std::string earlier_exr = read_text(exr), earlier_png = read_text(png);
    ASSERT_GT(earlier_png.size(), 1024u);
    const ToolRun r = run_limited(render_png_args(exr, png));
    expect_one_line_error(r, "render", exr, std::strerror(EFBIG));
    EXPECT_TRUE(read_text(exr) == earlier_exr);
    EXPECT_TRUE(read_text(png) == earlier_png);
    EXPECT_FALSE(has_temporaries(dir));
}

// A small tmpfs, filled: a real full disk (ENOSPC). Needs mount (root); skipped otherwise.
class TmpfsMount {
public:
    explicit TmpfsMount(const std::string& dir) : m_dir(dir) {
        const std::string mount = "mount -t tmpfs -o size=1m npf-publish-test " + shell_quote(dir) + " 2>/dev/null";
        m_mounted = std::system(mount.c_str()) == 0;
    }
    ~TmpfsMount() {
        if (!m_mounted) return;
        const int rc = std::system(("umount " + shell_quote(m_dir)).c_str());
        EXPECT_EQ(rc, 0) << "cannot unmount " << m_dir;
    }
    bool mounted() const { return m_mounted; }

private:
    std::string m_dir;
    bool m_mounted = false;
};

// Fills the file system of `dir` with `dir/filler`, then gives `room` bytes back (whole pages).
void fill_leaving(const std::string& dir, std::size_t room) {
    const std::string filler = dir + "/filler";
    const int fd = ::open(filler.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0) << std::strerror(errno);
    const std::vector<char> chunk(1 << 16, 'x');
    std::size_t size = 0;
    int error = 0;
    while (error == 0) {
        const ssize_t n = ::write(fd, chunk.data(), chunk.size());
        if (n < 0 && errno != EINTR) error = errno;
        if (n > 0) size += std::size_t(n);
    }
    EXPECT_EQ(error, ENOSPC);
    const std::size_t page = 4096, keep = size > room ? (size - room) / page * page : 0;
    EXPECT_EQ(::ftruncate(fd, off_t(keep)), 0);
    ::close(fd);
    struct statvfs vfs {};
    ASSERT_EQ(::statvfs(dir.c_str(), &vfs), 0);
    EXPECT_LT(std::size_t(vfs.f_bavail) * vfs.f_bsize, room + 2 * page);
}

TEST(PublishFaults, FullTmpfsKeepsEveryEarlierOutput) {
    const std::string dir = npf::testing::temporary_folder("publish-tmpfs");
    const TmpfsMount mount(dir);
    if (!mount.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root)";
    const std::string filler = dir + "/filler";
    for (const Writer& w : writers()) {
        const std::string out = dir + "/" + w.command + "-" + w.file;
        ASSERT_EQ(npf::testing::run_tool(w.args(out)).status, 0) << w.command;
        const std::string earlier = read_text(out);
        fill_leaving(dir, 0);
        const ToolRun r = npf::testing::run_tool(w.args(out));
        expect_one_line_error(r, w.command, out, std::strerror(ENOSPC));
        EXPECT_TRUE(read_text(out) == earlier) << w.command << " changed the earlier output";
        ::unlink(filler.c_str());
    }
    // render --png with room for the EXR but not the PNG: the EXR is complete, the PNG fails,
    // and neither earlier file changes.
    const std::string exr = dir + "/both.exr", png = dir + "/both.png";
    ASSERT_EQ(npf::testing::run_tool(render_png_args(exr, png)).status, 0);
    const std::string earlier_exr = read_text(exr), earlier_png = read_text(png);
    const std::size_t room = (earlier_exr.size() + 4095) / 4096 * 4096;
    ASSERT_GT(room - earlier_exr.size(), 256u) << "the new EXR (its header varies by a few bytes) must fit";
    fill_leaving(dir, room);
    const ToolRun r = npf::testing::run_tool(render_png_args(exr, png));
    expect_one_line_error(r, "render", png, std::strerror(ENOSPC));
    EXPECT_TRUE(read_text(exr) == earlier_exr) << "the earlier EXR changed";
    EXPECT_TRUE(read_text(png) == earlier_png) << "the earlier PNG changed";
    ::unlink(filler.c_str());
    EXPECT_FALSE(has_temporaries(dir));
}

}  // namespace
