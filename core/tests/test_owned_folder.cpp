// Folders a tool owns (npf/core/owned_folder.h) and the files it owns in them (OutputOptions::
// owned_by, npf/core/atomic_file.h): a link there is refused with a line naming it and where it
// points, never followed; emptying one removes links, not their targets; a folder held by its
// descriptor is not redirected by its name swapped for a link.
#include "error_of.h"
#include "run_tool.h"
#include "synthetic_rgl.h"

#include <npf/core/atomic_file.h>
#include <npf/core/owned_folder.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using npf::OwnedFolder, npf::testing::contains, npf::testing::error_of, npf::testing::read_text,
      npf::testing::write_text;

struct Place {
    std::string dir = npf::testing::temporary_folder("owned-folder");
    OwnedFolder user = OwnedFolder::user_folder(dir + "/out", "npf test", true);
    Place() {
        fs::create_directories(dir + "/victim/sub");
        write_text(dir + "/victim/a.txt", "a");
        write_text(dir + "/victim/sub/b.txt", "b");
    }
    bool victim_intact() const {
        return read_text(dir + "/victim/a.txt") == "a" && read_text(dir + "/victim/sub/b.txt") == "b" &&
               npf::testing::folder_entries(dir + "/victim") == std::vector<std::string>{"a.txt", "sub"};
    }
};

TEST(OwnedFolder, ALinkIsRefusedWithWhereItPoints) {
    Place p;
    fs::create_directory_symlink("../victim", p.dir + "/out/work");
    const std::string expected = p.dir + "/out/work: is a symbolic link (to ../victim): a folder npf test owns is never followed; remove it";
    EXPECT_EQ(error_of([&] { p.user.owned_child("work"); }), expected);
    EXPECT_EQ(error_of([&] { p.user.check_owned_child("work"); }), expected);
    write_text(p.dir + "/out/file", "x");
    EXPECT_EQ(error_of([&] { p.user.owned_child("file"); }),
              p.dir + "/out/file: is a regular file where npf test keeps a folder of its own: not used; remove it");
    EXPECT_FALSE(p.user.check_owned_child("missing"));
    EXPECT_TRUE(p.victim_intact());
}

TEST(OwnedFolder, EmptyingRemovesLinksNotWhatTheyPointTo) {
    Place p;
    const OwnedFolder work = p.user.owned_child("work", 0700);
    EXPECT_EQ(::access((p.dir + "/out/work").c_str(), F_OK), 0);
    fs::create_directories(p.dir + "/out/work/deep/er");
    write_text(p.dir + "/out/work/deep/er/f", "f");
    write_text(p.dir + "/out/work/g", "g");
    fs::create_directory_symlink("../../victim", p.dir + "/out/work/to-folder");
    fs::create_symlink("../../victim/a.txt", p.dir + "/out/work/to-file");
    fs::create_directory_symlink("../../../victim", p.dir + "/out/work/deep/to-folder");
    work.clear();
    EXPECT_TRUE(npf::testing::folder_entries(p.dir + "/out/work").empty());
    EXPECT_TRUE(p.victim_intact());
}

TEST(OwnedFolder, ItsNameSwappedForALinkRedirectsNothing) {
    Place p;
    const OwnedFolder work = p.user.owned_child("work");
    fs::rename(p.dir + "/out/work", p.dir + "/out/moved");
    fs::create_directory_symlink("../victim", p.dir + "/out/work");
    work.write_new_file("x", "through the descriptor");
    EXPECT_EQ(read_text(p.dir + "/out/moved/x"), "through the descriptor");
    npf::write_file_atomically(work.through("y"), "y", 1, npf::OutputOptions{"npf test", work.path_of("y")});
    EXPECT_EQ(read_text(p.dir + "/out/moved/y"), "y");
    EXPECT_TRUE(p.victim_intact());
    // Messages name the folder as people know it, not /proc/self/fd/N.
    EXPECT_EQ(work.shown("cannot create output in " + work.through("z").substr(0, work.through("z").size() - 2)),
              "cannot create output in " + p.dir + "/out/work");
    // Another process reopens it by name only if it is the same folder.
    EXPECT_TRUE(contains(error_of([&] { OwnedFolder::reopen(p.dir + "/out/work", work.device(), work.inode(), "npf test"); }),
                         "cannot open the folder npf test made"));
    fs::remove(p.dir + "/out/work");
    fs::create_directory(p.dir + "/out/work");
    EXPECT_EQ(error_of([&] { OwnedFolder::reopen(p.dir + "/out/work", work.device(), work.inode(), "npf test"); }),
              p.dir + "/out/work: is not the folder npf test made (another was put in its place): not used");
    EXPECT_NO_THROW(OwnedFolder::reopen(p.dir + "/out/moved", work.device(), work.inode(), "npf test"));
}

TEST(OwnedFolder, ItsFilesAreNeverOpenedThroughALink) {
    Place p;
    const OwnedFolder work = p.user.owned_child("work");
    fs::create_symlink("../../victim/a.txt", p.dir + "/out/work/link");
    fs::create_symlink("../../victim/new.txt", p.dir + "/out/work/dangling");
    const std::string link = p.dir + "/out/work/link: is a symbolic link (to ../../victim/a.txt): a file npf test owns is never followed; remove it";
    EXPECT_EQ(error_of([&] { work.create_file("link"); }), link);
    EXPECT_EQ(error_of([&] { work.open_file("link", true); }), link);
    EXPECT_EQ(error_of([&] { work.read_text("link", "a list", npf::kConfigTextBounds); }), link);
    EXPECT_TRUE(contains(error_of([&] { work.open_file("dangling", true); }), "is a symbolic link (to ../../victim/new.txt)"));
    EXPECT_FALSE(work.has_regular_file("link"));
    // Published as the tool's own file: refused, not followed; as a user's output: followed.
    EXPECT_EQ(error_of([&] { npf::write_file_atomically(work.through("link"), "x", 1, npf::OutputOptions{"npf test", work.path_of("link")}); }),
              link);
    EXPECT_TRUE(p.victim_intact());
    write_text(p.dir + "/out/work/staged", "staged bytes");
    fs::create_symlink("staged", p.dir + "/out/work/staged-link");
    EXPECT_TRUE(contains(error_of([&] { npf::publish_staged_file(work.through("staged-link"), p.dir + "/out/final"); }),
                         "is a symbolic link, not the finished file: never read through; not published"));
    EXPECT_FALSE(fs::exists(p.dir + "/out/final"));
    npf::write_file_atomically(p.dir + "/out/work/link", "x", 1);
    EXPECT_EQ(read_text(p.dir + "/victim/a.txt"), "x");
}

}  // namespace
