// hmp_manual OUT_DIR: writes hmp's manual pages (OUT_DIR/man/man1/hmp.1 and hmp-COMMAND.1, one per
// command) and its bash completion (OUT_DIR/bash-completion/completions/hmp) from the option tables of
// every command (host/cli/manual.hpp). Run by the build; its output is installed under share/.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "host/cli/commands.hpp"
#include "host/cli/manual.hpp"
#include "host/common/install_layout.hpp"

namespace {

namespace fs = std::filesystem;

bool write(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (out) return true;
  std::fprintf(stderr, "error: cannot write %s\n", file.c_str());
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace hmp::cli;
  if (argc != 2) {
    std::fprintf(stderr, "usage: hmp_manual OUT_DIR\n");
    return 2;
  }
  CLI::App program{kProgramDescription};
  Registry registry;
  for (const Command& c : kCommands) c.add(program, registry);
  const fs::path out = argv[1];
  const fs::path man = out / "man" / "man1", completions = out / "bash-completion" / "completions";
  std::error_code ec;
  fs::create_directories(man, ec);
  fs::create_directories(completions, ec);
  const std::string version = hmp::install::version_text();
  bool ok = write(man / "hmp.1", man_page(program, nullptr, version));
  for (const CLI::App* c : program.get_subcommands([](const CLI::App*) { return true; }))
    ok = write(man / (man_name(c) + ".1"), man_page(program, c, version)) && ok;
  ok = write(completions / "hmp", bash_completion(program)) && ok;
  return ok ? 0 : 1;
}
