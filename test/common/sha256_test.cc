// SPDX-License-Identifier: Apache-2.0
// SHA-256 against the FIPS 180-2 / NIST test vectors, split updates, and a file.

#include "common/sha256.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test/support/scratch_dir.h"

namespace wallcal {
namespace {

TEST(Sha256Test, MatchesTheStandardTestVectors) {
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(Sha256Hex(std::string(1000000, 'a')),
            "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256Test, SplitUpdatesGiveTheSameDigest) {
  const std::string text = "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq";
  for (size_t cut = 0; cut <= text.size(); cut += 7) {
    Sha256 hash;
    hash.Update(text.data(), cut);
    hash.Update(text.data() + cut, text.size() - cut);
    EXPECT_EQ(hash.Hex(), Sha256Hex(text)) << cut;
  }
}

TEST(Sha256Test, HashesAFileAndSaysWhenItCannot) {
  const testing_support::ScratchDir scratch("wallcal_sha256_test_");
  const std::filesystem::path path = scratch.path() / "wallcal_sha256_test.txt";
  std::ofstream(path, std::ios::binary) << "abc";
  EXPECT_EQ(Sha256OfFile(path.string()),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256OfFile((path.parent_path() / "no_such_file_here").string()), "");
}

}  // namespace
}  // namespace wallcal
