#pragma once
// The manual pages and the bash completion of hmp, written from the commands' option tables (the CLI11
// definitions that `--help` prints), so that neither can drift from the program. host/cli/manual_main.cpp
// writes them at build time; cmake/install.cmake installs them.
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace hmp::cli {

// roff (man(7)) of `hmp` (command null: the program, listing its commands) or of `hmp COMMAND`.
std::string man_page(const CLI::App& program, const CLI::App* command, std::string_view version);

// A bash completion script for `hmp`: the commands, each command's options, and files where an option or
// argument takes a value.
std::string bash_completion(const CLI::App& program);

// The man page's name of a command: "hmp" or "hmp-play".
std::string man_name(const CLI::App* command);

}  // namespace hmp::cli
