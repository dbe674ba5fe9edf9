// StagedDirectory: an output folder appears complete or not at all.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "groundline/core/atomic_file.h"
#include "test_data.h"

namespace groundline {
namespace {

namespace fs = std::filesystem;

using ::groundline::testing::ReadText;

TEST(StagedDirectory, NewFolderAppearsOnlyAtCommit) {
  const fs::path dir = ::groundline::testing::ScratchDir("staged_new");
  const fs::path out = dir / "run";
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(out);
  ASSERT_TRUE(staged.ok()) << staged.message();
  EXPECT_EQ(staged->path().parent_path(), fs::absolute(dir).lexically_normal());
  ASSERT_TRUE(core::WriteFileAtomically(staged->path() / "a.txt", "a").ok());
  ASSERT_TRUE(core::WriteFileAtomically(staged->path() / "sub" / "b.txt", "b").ok());
  EXPECT_FALSE(fs::exists(out));
  ASSERT_TRUE(staged->Commit().ok());
  EXPECT_EQ(ReadText(out / "a.txt"), "a");
  EXPECT_EQ(ReadText(out / "sub" / "b.txt"), "b");
  EXPECT_FALSE(fs::exists(staged->path()));
  // Nothing but the folder itself is left beside it.
  int entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++entries;
  EXPECT_EQ(entries, 1);
}

TEST(StagedDirectory, ExistingFolderIsMergedAndKeepsOtherFiles) {
  const fs::path dir = ::groundline::testing::ScratchDir("staged_merge");
  const fs::path out = dir / "run";
  ASSERT_TRUE(core::WriteFileAtomically(out / "old.txt", "kept").ok());
  ASSERT_TRUE(core::WriteFileAtomically(out / "a.txt", "before").ok());
  ASSERT_TRUE(core::WriteFileAtomically(out / "sub" / "c.txt", "kept too").ok());
  core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(out.string() + "/");
  ASSERT_TRUE(staged.ok()) << staged.message();
  ASSERT_TRUE(core::WriteFileAtomically(staged->path() / "a.txt", "after").ok());
  ASSERT_TRUE(core::WriteFileAtomically(staged->path() / "sub" / "b.txt", "b").ok());
  EXPECT_EQ(ReadText(out / "a.txt"), "before");
  ASSERT_TRUE(staged->Commit().ok());
  EXPECT_EQ(ReadText(out / "a.txt"), "after");
  EXPECT_EQ(ReadText(out / "old.txt"), "kept");
  EXPECT_EQ(ReadText(out / "sub" / "b.txt"), "b");
  EXPECT_EQ(ReadText(out / "sub" / "c.txt"), "kept too");
  EXPECT_FALSE(fs::exists(staged->path()));
}

TEST(StagedDirectory, UncommittedStagingIsRemovedAndTheFolderUntouched) {
  const fs::path dir = ::groundline::testing::ScratchDir("staged_abort");
  const fs::path out = dir / "run";
  fs::path staging;
  {
    core::Result<core::StagedDirectory> staged = core::StagedDirectory::Create(out);
    ASSERT_TRUE(staged.ok()) << staged.message();
    staging = staged->path();
    ASSERT_TRUE(core::WriteFileAtomically(staging / "half.txt", "half").ok());
    EXPECT_TRUE(fs::exists(staging / "half.txt"));
  }
  EXPECT_FALSE(fs::exists(staging));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace groundline
