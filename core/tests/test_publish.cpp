// Publishing outputs (docs/reliability.md, "1. Publishing outputs"): what is at the destination
// decides how an output is published (a regular file replaced atomically, a link followed, a
// device or FIFO written through, a folder or socket refused), the temporary cannot be hijacked,
// and every writer (convert, synth, render with and without --png, edit, display) goes through
// it. The fault tests (PublishFaults) fill the disk during each writer: under a file size limit
// (always) and on a real tmpfs (where mount is permitted), and find the earlier outputs intact.
//
// Device nodes are private copies made with mknod in the test folder (the null device, 1:3, and
// the full device, 1:7), so that a regression replaces a node there, never the machine's /dev/null.
//
// Here the library (AtomicOutput, write_file_atomically); the command line:
// test_publish_cli.cpp; the faults: test_publish_faults.cpp.
#include "publish_checks.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/atomic_file.h>
#include <npf/core/error.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

namespace {

using namespace npf::testing::publish;

TEST(PublishAtomic, ReplacesARegularFileAndLeavesNothingBeside) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string path = dir + "/out.bin";
    npf::write_file_atomically(path, "first", 5);
    ASSERT_TRUE(write_text(dir + "/other", "x"));
    npf::write_file_atomically(path, "second", 6);
    EXPECT_EQ(read_text(path), "second");
    EXPECT_EQ(kind_of(path), mode_t(S_IFREG));
    EXPECT_EQ(folder_entries(dir), (std::vector<std::string>{"other", "out.bin"}));
}

// Item 3 of issue 17: `<out>.tmp-<pid>-<n>` could be predicted, and a link planted there was
// followed. Links are planted at every such name the old scheme would use next.
TEST(PublishAtomic, PlantedLinkAtThePredictableTemporaryNameIsNotFollowed) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string victim = dir + "/victim.txt", out = dir + "/out.bin";
    ASSERT_TRUE(write_text(victim, "precious"));
    long next = 0;
    {
        // The old scheme's counter, read off a temporary name ("...tmp-PID-N"); 0 if not that scheme.
        npf::AtomicOutput probe(dir + "/probe.bin");
        const std::string t = probe.temporary_path();
        const std::string marker = ".tmp-" + std::to_string(::getpid()) + "-";
        const std::size_t at = t.find(marker);
        if (at != std::string::npos) next = std::atol(t.c_str() + at + marker.size()) + 1;
    }
    std::vector<std::string> planted;
    for (long k = 0; k < 8; ++k) {
        for (long n : {k, next + k}) {
            const std::string link = out + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(n);
            if (::symlink(victim.c_str(), link.c_str()) == 0) planted.push_back(link);
        }
    }
    npf::write_file_atomically(out, "new output", 10);
    EXPECT_EQ(read_text(victim), "precious");
    EXPECT_EQ(kind_of(out), mode_t(S_IFREG));
    EXPECT_EQ(read_text(out), "new output");
    for (const std::string& link : planted) EXPECT_EQ(kind_of(link), mode_t(S_IFLNK)) << link;
}

// PUBLISH-NEW-API-BEGIN (tests of functions the old AtomicOutput did not have)

TEST(PublishAtomic, TemporaryIsCreatedExclusivelyUnderARandomName) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string path = dir + "/out.bin";
    {
        npf::AtomicOutput a(path), b(path);
        EXPECT_NE(a.temporary_path(), b.temporary_path());
        for (const npf::AtomicOutput* o : {&a, &b}) {
            const std::string& t = o->temporary_path();
            ASSERT_EQ(t.rfind(path + ".tmp-", 0), 0u) << t;
            const std::string suffix = t.substr(path.size() + 5);
            EXPECT_EQ(suffix.size(), 16u) << t;
            EXPECT_EQ(suffix.find_first_not_of("0123456789abcdef"), std::string::npos) << t;
            EXPECT_EQ(kind_of(t), mode_t(S_IFREG)) << "created when the output is, not when first written";
        }
        EXPECT_FALSE(a.writes_through());
    }
    EXPECT_TRUE(folder_entries(dir).empty()) << "no commit: both temporaries removed";
}

// The temporary is written through its descriptor: a link swapped in for its name later gets
// nothing, and the swap is found before anything is published.
TEST(PublishAtomic, SwappedTemporaryIsNotPublished) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string victim = dir + "/victim.txt", out = dir + "/out.bin";
    ASSERT_TRUE(write_text(victim, "precious"));
    ASSERT_TRUE(write_text(out, "earlier"));
    try {
        npf::AtomicOutput o(out);
        ASSERT_EQ(o.write_at(0, "abc", 3), 3u);
        ASSERT_EQ(::unlink(o.temporary_path().c_str()), 0);
        ASSERT_EQ(::symlink(victim.c_str(), o.temporary_path().c_str()), 0);
        ASSERT_EQ(o.write_at(3, "def", 3), 3u);
        o.commit();
        ADD_FAILURE() << "published a swapped temporary";
    } catch (const npf::Error& e) {
        EXPECT_EQ(e.source(), out);
        EXPECT_TRUE(contains(e.what(), "was replaced while it was written")) << e.what();
    }
    EXPECT_EQ(read_text(victim), "precious");
    EXPECT_EQ(read_text(out), "earlier");
}

TEST(PublishAtomic, WriteErrorsAreKeptAndReported) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const std::string out = dir + "/out.bin";
    ASSERT_TRUE(write_text(out, "earlier"));
    {
        // A file size limit: the write stops short with EFBIG, which commit() reports.
        struct sigaction ignore {}, old_action {};
        ignore.sa_handler = SIG_IGN;
        ::sigaction(SIGXFSZ, &ignore, &old_action);
        struct rlimit old_limit {};
        ::getrlimit(RLIMIT_FSIZE, &old_limit);
        const std::vector<char> big(1 << 16, 'x');
        std::string message;
        {
            npf::AtomicOutput o(out);
            struct rlimit small = old_limit;
            small.rlim_cur = 4096;
            ::setrlimit(RLIMIT_FSIZE, &small);
            const std::size_t written = o.write_at(0, big.data(), big.size());
            ::setrlimit(RLIMIT_FSIZE, &old_limit);
            EXPECT_LT(written, big.size());
            EXPECT_EQ(o.write_at(written, "more", 4), 0u) << "a failed output takes no more writes";
            try {
                o.commit();
            } catch (const npf::Error& e) {
                message = e.what();
            }
        }
        ::sigaction(SIGXFSZ, &old_action, nullptr);
        EXPECT_EQ(message, out + ": cannot write: " + std::strerror(EFBIG));
    }
    EXPECT_EQ(read_text(out), "earlier");
    EXPECT_EQ(folder_entries(dir), std::vector<std::string>{"out.bin"});
}

TEST(PublishAtomic, WhatIsAtTheDestinationDecides) {
    const std::string dir = npf::testing::temporary_folder("publish");
    const auto error_of = [](const std::string& path) -> std::string {
        try {
            npf::write_file_atomically(path, "data", 4);
        } catch (const npf::Error& e) {
            EXPECT_EQ(e.source(), path) << e.what();
            return e.what();
        }
        return "";
    };

    // A folder, a socket, a dangling link, a link to a folder: refused, left as they are.
    const std::string folder = dir + "/folder";
    ASSERT_EQ(::mkdir(folder.c_str(), 0755), 0);
    EXPECT_EQ(error_of(folder), folder + ": is a directory, not a file: cannot move an output over it");
    EXPECT_TRUE(contains(error_of(folder + "/"), "names a folder, not a file"));
    EXPECT_TRUE(folder_entries(folder).empty());

    const std::string socket_path = dir + "/socket";
    const int sock = ::socket(AF_UNIX, SOCK_STREAM, 0);
    ASSERT_GE(sock, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    ASSERT_LT(socket_path.size(), sizeof address.sun_path);
    std::strcpy(address.sun_path, socket_path.c_str());
    ASSERT_EQ(::bind(sock, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
    EXPECT_TRUE(contains(error_of(socket_path), ": is a socket: not written")) << error_of(socket_path);
    EXPECT_EQ(kind_of(socket_path), mode_t(S_IFSOCK));
    ::close(sock);

    const std::string dangling = dir + "/dangling";
    ASSERT_EQ(::symlink("nowhere", dangling.c_str()), 0);
    EXPECT_EQ(error_of(dangling), dangling + ": is a symbolic link to nowhere, which does not exist: not followed "
                                             "(remove the link or create its target)");
    EXPECT_EQ(kind_of(dangling), mode_t(S_IFLNK));
    EXPECT_EQ(kind_of(dir + "/nowhere"), mode_t(0));

    const std::string to_folder = dir + "/to_folder";
    ASSERT_EQ(::symlink("folder", to_folder.c_str()), 0);
    EXPECT_TRUE(contains(error_of(to_folder), "is a symbolic link to a directory, not a file")) << error_of(to_folder);

    // A missing folder, an empty name.
    const std::string missing = dir + "/no/such/folder/x.bin";
    EXPECT_EQ(error_of(missing), missing + ": cannot create output in " + dir + "/no/such/folder: " + std::strerror(ENOENT));
    EXPECT_THROW(npf::write_file_atomically("", "x", 1), npf::Error);

    // A link to a regular file: followed; the link stays, its target gets the output.
    ASSERT_TRUE(write_text(dir + "/target.bin", "old"));
    const std::string link = dir + "/link";
    ASSERT_EQ(::symlink("target.bin", link.c_str()), 0);
    EXPECT_EQ(error_of(link), "");
    EXPECT_EQ(kind_of(link), mode_t(S_IFLNK));
    EXPECT_EQ(read_text(dir + "/target.bin"), "data");

    // A FIFO: written through. Opened here for reading and writing first, so that nothing blocks
    // and a regression (the FIFO replaced by a file) shows as an empty read, not a hang.
    const std::string fifo = dir + "/fifo";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
    const int reader = ::open(fifo.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
    ASSERT_GE(reader, 0);
    EXPECT_EQ(error_of(fifo), "");
    char got[16] = {};
    EXPECT_EQ(::read(reader, got, sizeof got), 4);
    EXPECT_EQ(std::string(got), "data");
    ::close(reader);
    EXPECT_EQ(kind_of(fifo), mode_t(S_IFIFO));

    // Character devices: written through (the null device discards, the full one says why not).
    const std::string null = null_destination(dir);
    if (!null.empty()) {
        EXPECT_EQ(error_of(null), "");
        EXPECT_TRUE(is_char_device(null, 3));
    }
    const std::string full = device_node(dir, "full", 7);
    if (!full.empty()) {
        EXPECT_EQ(error_of(full), full + ": cannot write: " + std::strerror(ENOSPC));
        EXPECT_TRUE(is_char_device(full, 7));
    }
    const std::string block = dir + "/block";
    if (::mknod(block.c_str(), S_IFBLK | 0600, makedev(7, 0)) == 0) {
        EXPECT_TRUE(contains(error_of(block), ": is a block device: not written")) << error_of(block);
        EXPECT_EQ(kind_of(block), mode_t(S_IFBLK));
    }
    EXPECT_FALSE(has_temporaries(dir));
}

TEST(PublishAtomic, CheckOutputPathFailsAsPublishingWouldAndLeavesNothing) {
    const std::string dir = npf::testing::temporary_folder("publish");
    EXPECT_NO_THROW(npf::check_output_path(dir + "/fine.exr"));
    EXPECT_THROW(npf::check_output_path(dir), npf::Error);
    EXPECT_THROW(npf::check_output_path(dir + "/missing/x.exr"), npf::Error);
    EXPECT_TRUE(folder_entries(dir).empty());
}

// PUBLISH-NEW-API-END

}  // namespace
