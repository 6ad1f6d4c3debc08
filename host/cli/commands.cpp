#include "host/cli/commands.hpp"

#include <cstdio>

#include "host/common/printable.hpp"

namespace hmp::cli {

namespace {

// Every option that takes a value refuses an empty one: CLI11 takes "" for a number as 0 (--crf '' was
// lossless, --ms '' a 0 ms note) and for an optional one as not given (--to '' was the song's end).
void refuse_empty_values(CLI::App& app) {
  const CLI::Validator non_empty(
      [](std::string& text) { return text.empty() ? std::string("an empty value") : std::string(); }, "", "non-empty");
  for (CLI::Option* option : app.get_options())
    if (option->get_type_size_max() > 0) option->check(non_empty);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) refuse_empty_values(*sub);
}

}  // namespace

int Registry::run() const { return action_ ? run_command(action_) : kExitBadInput; }

int run_cli(int argc, char** argv, void (*add_commands)(CLI::App&, Registry&)) {
  CLI::App app{kProgramDescription};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_string());
  Registry registry;
  add_commands(app, registry);
  refuse_empty_values(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (try --help)\n", terminal_line(e.what()).c_str());
    return kExitBadInput;
  }
  return registry.run();
}

}  // namespace hmp::cli
