// API tokens (api_tokens.h): issued, verified, rotated and revoked through the files serve and the
// holders keep; the store holds no token; files others may read are refused.
#include "api/api_tokens.h"

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "util/temporary_directory_testing.h"

namespace mocap::api {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ApiTokens, IssueVerifyRotateRevoke) {
  const testing::TemporaryDirectory temp("api_tokens");
  const std::string store = temp.File("tokens"), alice = temp.File("alice.token"), bob = temp.File("bob.token");
  const std::string a = IssueToken(store, "alice", ApiRole::kOperator, alice);
  const std::string b = IssueToken(store, "bob", ApiRole::kViewer, bob);
  EXPECT_EQ(a.size(), 64u);
  EXPECT_NE(a, b);
  EXPECT_EQ(ReadTokenFile(alice), a);
  struct stat st {};
  ASSERT_EQ(stat(store.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  ASSERT_EQ(stat(alice.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(Slurp(store).find(a), std::string::npos) << "the store holds a token";

  TokenVerifier verifier(store);
  EXPECT_EQ(verifier.Verify(a, 0)->name, "alice");
  EXPECT_EQ(verifier.Verify(a, 0)->role, ApiRole::kOperator);
  EXPECT_EQ(verifier.Verify(b, 0)->role, ApiRole::kViewer);
  EXPECT_FALSE(verifier.Verify(a + "0", 0).has_value());
  EXPECT_FALSE(verifier.Verify("", 0).has_value());

  // Rotation: the old token stops working once serve re-reads the store (at most a second).
  const std::string rotated = IssueToken(store, "alice", ApiRole::kOperator, alice);
  EXPECT_TRUE(verifier.Verify(a, 500'000'000).has_value());  // not looked at again yet
  EXPECT_FALSE(verifier.Verify(a, 2'000'000'000).has_value());
  EXPECT_TRUE(verifier.Verify(rotated, 2'000'000'000).has_value());
  EXPECT_TRUE(RevokeToken(store, "bob"));
  EXPECT_FALSE(RevokeToken(store, "bob"));
  EXPECT_FALSE(verifier.Verify(b, 4'000'000'000).has_value());
  EXPECT_EQ(verifier.size(), 1u);
}

TEST(ApiTokens, OpenFilesAndBadStoresAreRefusedNamingThem) {
  const testing::TemporaryDirectory temp("api_tokens_bad");
  const std::string file = temp.File("open.token");
  WriteTokenFile(file, GenerateToken());
  chmod(file.c_str(), 0644);
  try {
    ReadTokenFile(file);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("readable by group or others (mode 644)"), std::string::npos) << e.what();
  }
  const std::string hash(64, 'a');
  for (const auto& [text, reason] : std::vector<std::pair<std::string, std::string>>{
           {"alice operator\n", "s:1: expected NAME ROLE HASH"},
           {"alice root " + hash + "\n", "role 'root'"},
           {"a/b operator " + hash + "\n", "token name 'a/b'"},
           {"alice operator " + hash + "\nalice viewer " + hash + "\n", "s:2: token name 'alice' appears twice"},
           {"alice operator ABC\n", "hash"}}) {
    try {
      ParseTokenStore(text, "s");
      ADD_FAILURE() << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(ReadTokenStore(temp.File("absent")).empty());
  EXPECT_THROW(IssueToken(temp.File("s"), "../x", ApiRole::kViewer, temp.File("x")), std::invalid_argument);
}

// `sudo mocap-hub tokens new` on an installed hub: the store stays the service user's (serve runs
// as that user and must still read it) and the holder's file becomes its directory owner's.
TEST(ApiTokens, RootKeepsTheStoreItsOwnersAndGivesTheHolderTheirFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root (chown)";
  const testing::TemporaryDirectory temp("api_tokens_owner");
  const std::string service = temp.File("api-auth"), home = temp.File("home");
  ASSERT_EQ(::mkdir(service.c_str(), 0700), 0);
  ASSERT_EQ(::mkdir(home.c_str(), 0700), 0);
  ASSERT_EQ(::chown(service.c_str(), 4242, 4243), 0);
  ASSERT_EQ(::chown(home.c_str(), 4244, 4245), 0);
  const std::string store = service + "/tokens";
  IssueToken(store, "local", ApiRole::kOperator, service + "/operator.token");
  IssueToken(store, "alice", ApiRole::kOperator, home + "/token");
  struct stat st {};
  ASSERT_EQ(stat(store.c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 4242u);
  EXPECT_EQ(st.st_gid, 4243u);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  ASSERT_EQ(stat((home + "/token").c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 4244u);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  // Files root's own directories hold stay root's.
  IssueToken(temp.File("root_store"), "bob", ApiRole::kViewer, temp.File("bob.token"));
  ASSERT_EQ(stat(temp.File("root_store").c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, 0u);
}

}  // namespace
}  // namespace mocap::api
