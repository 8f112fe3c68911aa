// `tokens new|revoke|list`: who may use serve's API (api/api_tokens.h). A token is issued into a
// holder's file (mode 0600, never printed) and its hash into serve's store (DIR/tokens, serve
// --api-auth DIR); serve re-reads the store within a second, so issuing a name again rotates its
// token and revoking ends it, both without a restart.
#include <cstdio>
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "api/api_tokens.h"
#include "cli/commands.h"

namespace mocap {
namespace {

struct TokensArgs {
  std::string dir = "api-auth";
  std::string name;
  std::string role = "viewer";
  std::string out;
  bool json = false;
};

std::string StoreOf(const TokensArgs& a) { return a.dir + "/tokens"; }

void RunNew(const TokensArgs& a) {
  const std::optional<api::ApiRole> role = api::ParseRole(a.role);
  if (!role) throw UsageError("--role " + a.role + ": viewer or operator");
  if (!api::ValidTokenName(a.name)) throw UsageError("NAME '" + a.name + "': 1-64 letters, digits, '.', '-' or '_'");
  const std::string out = a.out.empty() ? a.dir + "/" + a.name + ".token" : a.out;
  api::IssueToken(StoreOf(a), a.name, *role, out);
  std::printf("%s: token '%s' (%s) for its holder; %s updated (serve follows within a second)\n", out.c_str(),
              a.name.c_str(), api::RoleName(*role), StoreOf(a).c_str());
}

void RunRevoke(const TokensArgs& a) {
  if (!api::RevokeToken(StoreOf(a), a.name)) throw std::runtime_error(StoreOf(a) + ": no token '" + a.name + "'");
  std::printf("%s: token '%s' revoked\n", StoreOf(a).c_str(), a.name.c_str());
}

void RunList(const TokensArgs& a) {
  nlohmann::json out = nlohmann::json::array();
  for (const api::TokenEntry& e : api::ReadTokenStore(StoreOf(a))) {
    out.push_back({{"name", e.name}, {"role", api::RoleName(e.role)}});
    if (!a.json) std::printf("%s %s\n", e.name.c_str(), api::RoleName(e.role));
  }
  if (a.json) std::printf("%s\n", out.dump(2).c_str());
}

}  // namespace

void AddTokensCommands(CLI::App& app) {
  CLI::App& group = CommandGroup(app, "tokens");
  auto args = std::make_shared<TokensArgs>();
  const auto dir = [&](CLI::App* command) {
    command->add_option("--dir", args->dir, "serve's --api-auth directory")->capture_default_str();
  };
  CLI::App* make = group.add_subcommand("new", "Issue (or rotate) the API token NAME into a file of its own");
  make->add_option("NAME", args->name, "Who holds it (letters, digits, '.', '-', '_')")->required();
  make->add_option("--role", args->role, "viewer (reads) or operator (everything)")->capture_default_str();
  make->add_option("--out", args->out, "The holder's token file (mode 0600; default DIR/NAME.token)");
  dir(make);
  make->callback([args] { RunNew(*args); });
  CLI::App* revoke = group.add_subcommand("revoke", "End the API token NAME");
  revoke->add_option("NAME", args->name, "The token's name")->required();
  dir(revoke);
  revoke->callback([args] { RunRevoke(*args); });
  CLI::App* list = group.add_subcommand("list", "Names and roles of the API tokens (never the tokens)");
  list->add_flag("--json", args->json, "One JSON array on stdout");
  dir(list);
  list->callback([args] { RunList(*args); });
}

}  // namespace mocap
