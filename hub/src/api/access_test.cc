// The access rules (access.h): the probe's attacks each refused by the rule meant for it, the
// operator's own requests let through.
#include "api/access.h"

#include <gtest/gtest.h>

namespace mocap::api {
namespace {

class AccessTest : public ::testing::Test {
 protected:
  AccessDecision Decide(AccessRequest request) {
    return DecideAccess(request, options_, [](const std::string& token) -> std::optional<ApiPrincipal> {
      if (token == "op-token") return ApiPrincipal{"alice", ApiRole::kOperator};
      if (token == "view-token") return ApiPrincipal{"bob", ApiRole::kViewer};
      return std::nullopt;
    }, sessions_, 1000);
  }
  static AccessRequest Get(const std::string& path, const std::string& authorization = "Bearer op-token") {
    AccessRequest r;
    r.method = "GET";
    r.path = path;
    r.host = "127.0.0.1:7801";
    r.authorization = authorization;
    return r;
  }
  static AccessRequest Post(const std::string& path, const std::string& authorization = "Bearer op-token") {
    AccessRequest r = Get(path, authorization);
    r.method = "POST";
    r.content_type = "application/json";
    return r;
  }
  AccessOptions options_;
  LoginSessions sessions_;
};

TEST_F(AccessTest, NoTokenNoAnswerFromLanOrLocalhost) {
  for (const char* host : {"127.0.0.1:7801", "192.168.10.5:7801", "[::1]:7801", "localhost:7801"}) {
    AccessRequest r = Get("/api/status", "");
    r.host = host;
    EXPECT_EQ(Decide(r).status, 401) << host;
    r.authorization = "Bearer wrong";
    EXPECT_EQ(Decide(r).status, 401) << host;
    r.authorization = "Basic b3A6dG9rZW4=";
    EXPECT_EQ(Decide(r).status, 401) << host;
  }
  EXPECT_EQ(Decide(Get("/api/status")).status, 0);
  EXPECT_EQ(Decide(Get("/api/status")).who.name, "alice");
  EXPECT_EQ(Decide(Post("/api/capture/start", "")).status, 401);
}

TEST_F(AccessTest, ViewersReadOperatorsSteer) {
  EXPECT_EQ(Decide(Get("/api/sessions", "Bearer view-token")).status, 0);
  const AccessDecision refused = Decide(Post("/api/capture/stop", "Bearer view-token"));
  EXPECT_EQ(refused.status, 403);
  EXPECT_NE(refused.reason.find("'bob' is a viewer"), std::string::npos) << refused.reason;
  AccessRequest remove = Post("/api/masks", "Bearer view-token");
  remove.method = "DELETE";
  EXPECT_EQ(Decide(remove).status, 403);
  EXPECT_EQ(Decide(Post("/api/capture/stop")).status, 0);
  AccessRequest ws = Get("/api/live", "Bearer view-token");
  ws.websocket = true;
  EXPECT_EQ(Decide(ws).status, 0);
}

// The probe: a web page the operator visits POSTed text/plain with a foreign Origin (no CORS
// preflight) and started and stopped captures.
TEST_F(AccessTest, CrossOriginStateChangesAreRefused) {
  AccessRequest r = Post("/api/capture/start");
  r.origin = "http://evil.example";
  EXPECT_EQ(Decide(r).status, 403);
  r.origin = "http://127.0.0.1:7801";
  EXPECT_EQ(Decide(r).status, 0);
  r.origin = "null";
  EXPECT_EQ(Decide(r).status, 403);
  // Without JSON or the custom header: a form or a text/plain fetch.
  r = Post("/api/capture/start");
  r.content_type = "text/plain";
  EXPECT_EQ(Decide(r).status, 403);
  r.content_type = "application/x-www-form-urlencoded";
  EXPECT_EQ(Decide(r).status, 403);
  r.content_type = "application/jsonp";
  EXPECT_EQ(Decide(r).status, 403);
  r.content_type = "";
  r.custom = "1";
  EXPECT_EQ(Decide(r).status, 0);
  r = Post("/api/capture/start");
  r.content_type = "application/json; charset=utf-8";
  EXPECT_EQ(Decide(r).status, 0);
  r.sec_fetch_site = "cross-site";
  EXPECT_EQ(Decide(r).status, 403);
  r.sec_fetch_site = "same-origin";
  EXPECT_EQ(Decide(r).status, 0);
  // Login itself is a state change: the same rules, before any credential.
  AccessRequest login = Post("/api/login", "");
  login.origin = "http://evil.example";
  EXPECT_EQ(Decide(login).status, 403);
  login.origin = "";
  EXPECT_EQ(Decide(login).status, 0);
  // A foreign page may read nothing either way (no CORS), and a GET carries no cookie of ours
  // (SameSite=Strict): its Origin alone is no reason to refuse a read with a token.
  AccessRequest read = Get("/api/status");
  read.origin = "http://evil.example";
  EXPECT_EQ(Decide(read).status, 0);
}

TEST_F(AccessTest, ForeignHostsAndWebSocketOriginsAreRefused) {
  AccessRequest r = Get("/api/status");
  for (const char* host : {"evil.example", "evil.example:7801", "", "127.0.0.1:80:80", "[::1", "1.2.3.4:x"}) {
    r.host = host;
    EXPECT_EQ(Decide(r).status, 421) << host;
  }
  options_.host_names = {"hub.lab"};
  r.host = "HUB.lab:7801";
  EXPECT_EQ(Decide(r).status, 0);
  AccessRequest ws = Get("/api/live");
  ws.websocket = true;
  ws.origin = "http://evil.example";
  EXPECT_EQ(Decide(ws).status, 403);
  ws.origin = "http://127.0.0.1:7801";
  EXPECT_EQ(Decide(ws).status, 0);
}

TEST_F(AccessTest, ConsoleLoginsByCookie) {
  const std::string id = sessions_.Create({"carol", ApiRole::kOperator}, 1000);
  AccessRequest r = Post("/api/capture/start", "");
  r.cookie = "theme=dark; " + std::string(kSessionCookie) + "=" + id;
  EXPECT_EQ(Decide(r).status, 0);
  EXPECT_EQ(Decide(r).who.name, "carol");
  r.cookie = std::string(kSessionCookie) + "=" + id + "x";
  EXPECT_EQ(Decide(r).status, 401);
  EXPECT_FALSE(sessions_.Find(id, 1000 + LoginSessions::kIdleNs + 2000).has_value());  // idle too long
  const std::string again = sessions_.Create({"carol", ApiRole::kOperator}, 1000);
  sessions_.Remove(again);
  EXPECT_FALSE(sessions_.Find(again, 1000).has_value());
  // At most kMaxSessions: the oldest goes.
  const std::string first = sessions_.Create({"x", ApiRole::kViewer}, 1);
  for (size_t i = 0; i < LoginSessions::kMaxSessions; ++i) sessions_.Create({"y", ApiRole::kViewer}, 2 + i);
  EXPECT_FALSE(sessions_.Find(first, 10).has_value());
}

TEST_F(AccessTest, WithoutTokensEveryoneOperatesButTheBrowserRulesHold) {
  options_.tokens_required = false;
  EXPECT_EQ(Decide(Post("/api/capture/start", "")).status, 0);
  AccessRequest r = Post("/api/capture/start", "");
  r.origin = "http://evil.example";
  EXPECT_EQ(Decide(r).status, 403);
  r = Get("/api/status", "");
  r.host = "evil.example";
  EXPECT_EQ(Decide(r).status, 421);
}

TEST(AccessHeaders, BearerAndCookies) {
  EXPECT_EQ(BearerToken("Bearer abc"), "abc");
  EXPECT_EQ(BearerToken("bearer   abc  "), "abc");
  EXPECT_EQ(BearerToken("Basic abc"), "");
  EXPECT_EQ(BearerToken("Bearer"), "");
  EXPECT_EQ(CookieValue("a=1; mocap_session=xyz; b=2", "mocap_session"), "xyz");
  EXPECT_EQ(CookieValue("xmocap_session=1", "mocap_session"), "");
  EXPECT_EQ(CookieValue("", "mocap_session"), "");
}

}  // namespace
}  // namespace mocap::api
