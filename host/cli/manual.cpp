#include "host/cli/manual.hpp"

#include <vector>

namespace hmp::cli {

namespace {

// Every page's EXIT STATUS section: the same rule for hmp and each of its commands.
constexpr const char* kExitStatus =
    ".SH EXIT STATUS\n0 on success, 1 when a run failed, 2 on bad input (a file, an option): one line on standard "
    "error says what and where.\n";

// Text as roff: backslashes and hyphens escaped, no line starting with a control character.
std::string roff(std::string_view text) {
  std::string out;
  bool line_start = true;
  for (const char c : text) {
    if (line_start && (c == '.' || c == '\'')) out += "\\&";
    if (c == '\\') {
      out += "\\e";
    } else if (c == '-') {
      out += "\\-";
    } else {
      out += c;
    }
    line_start = c == '\n';
  }
  return out;
}

std::vector<const CLI::App*> commands_of(const CLI::App& program) {
  return program.get_subcommands([](const CLI::App*) { return true; });
}

std::vector<const CLI::Option*> options_of(const CLI::App& command) {
  return command.get_options([](const CLI::Option* o) { return !o->get_positional(); });
}

std::vector<const CLI::Option*> arguments_of(const CLI::App& command) {
  return command.get_options([](const CLI::Option* o) { return o->get_positional(); });
}

// "-h, --help" with its value's type: "--out FILE".
std::string option_names(const CLI::Option& o) {
  std::string names;
  for (const std::string& s : o.get_snames()) names += (names.empty() ? "" : ", ") + std::string("-") + s;
  for (const std::string& l : o.get_lnames()) names += (names.empty() ? "" : ", ") + std::string("--") + l;
  return names;
}

bool takes_value(const CLI::Option& o) { return o.get_items_expected_max() > 0; }

std::string value_type(const CLI::Option& o) {
  std::string type = o.get_type_name();
  return type.empty() ? "VALUE" : type;
}

std::string header(std::string_view name, std::string_view version) {
  std::string upper;
  for (const char c : name) upper += static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
  return ".TH " + roff(upper) + " 1 \"\" \"hmp " + roff(version) + "\" \"Haptic Music Player\"\n";
}

}  // namespace

std::string man_name(const CLI::App* command) { return command == nullptr ? "hmp" : "hmp-" + command->get_name(); }

std::string man_page(const CLI::App& program, const CLI::App* command, std::string_view version) {
  std::string page = header(man_name(command), version);
  page += ".SH NAME\n" + roff(man_name(command)) + " \\- ";
  if (command == nullptr) {
    page += roff(program.get_description()) + "\n";
    page += ".SH SYNOPSIS\n.B hmp\n.I COMMAND\n[\\fIOPTIONS\\fR]\n.br\n.B hmp \\-\\-version\n";
    page += ".SH COMMANDS\n";
    for (const CLI::App* c : commands_of(program)) {
      page += ".TP\n.B " + roff(c->get_name()) + "\n" + roff(c->get_description()) + " (\\fB" + roff(man_name(c)) +
              "\\fR(1))\n";
    }
    page += ".SH OPTIONS\n.TP\n.B \\-\\-version\nThe version of hmp and of its device protocol.\n";
    page += ".TP\n.B \\-h, \\-\\-help\nThe commands, or with a command its options.\n";
    page += kExitStatus;
    page += ".SH SEE ALSO\n";
    std::string sep;
    for (const CLI::App* c : commands_of(program)) {
      page += sep + ".BR " + roff(man_name(c)) + " (1)";
      sep = ",\n";
    }
    return page + "\n";
  }
  page += roff(command->get_description()) + "\n";
  page += ".SH SYNOPSIS\n.B hmp " + roff(command->get_name()) + "\n[\\fIOPTIONS\\fR]";
  for (const CLI::Option* a : arguments_of(*command)) {
    const std::string name = "\\fI" + roff(a->get_name()) + "\\fR";
    page += a->get_required() ? "\n" + name : "\n[" + name + "]";
    if (a->get_expected_max() > 1) page += "...";
  }
  page += "\n.SH DESCRIPTION\n" + roff(command->get_description()) + ".\n";
  if (const auto args = arguments_of(*command); !args.empty()) {
    page += ".SH ARGUMENTS\n";
    for (const CLI::Option* a : args)
      page += ".TP\n.I " + roff(a->get_name()) + "\n" + roff(a->get_description()) + "\n";
  }
  page += ".SH OPTIONS\n";
  for (const CLI::Option* o : options_of(*command)) {
    page += ".TP\n\\fB" + roff(option_names(*o)) + "\\fR";
    if (takes_value(*o)) page += " \\fI" + roff(value_type(*o)) + "\\fR";
    page += "\n" + roff(o->get_description());
    if (!o->get_default_str().empty()) page += " (default: " + roff(o->get_default_str()) + ")";
    if (o->get_required()) page += " (required)";
    page += "\n";
  }
  if (const std::string footer = command->get_footer(); !footer.empty()) page += ".SH NOTES\n" + roff(footer) + "\n";
  page += kExitStatus;
  page += ".SH SEE ALSO\n.BR hmp (1)\n";
  return page;
}

std::string bash_completion(const CLI::App& program) {
  std::string commands, cases;
  for (const CLI::App* c : commands_of(program)) {
    commands += (commands.empty() ? "" : " ") + c->get_name();
    std::string options, valued;
    for (const CLI::Option* o : options_of(*c)) {
      for (const std::string& l : o->get_lnames()) {
        options += (options.empty() ? "" : " ") + std::string("--") + l;
        if (takes_value(*o)) valued += (valued.empty() ? "" : "|") + std::string("--") + l;
      }
      for (const std::string& s : o->get_snames()) {
        options += (options.empty() ? "" : " ") + std::string("-") + s;
        if (takes_value(*o)) valued += (valued.empty() ? "" : "|") + std::string("-") + s;
      }
    }
    cases += "    " + c->get_name() + ")\n      options=\"" + options + "\"\n      valued=\"" + valued + "\" ;;\n";
  }
  return "# bash completion for hmp, written from its option tables (host/cli/manual.cpp): do not edit.\n"
         "_hmp() {\n"
         "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
         "  local options='' valued=''\n"
         "  if [ \"$COMP_CWORD\" -eq 1 ]; then\n"
         "    COMPREPLY=($(compgen -W \"" +
         commands +
         " --help --version\" -- \"$cur\"))\n"
         "    return\n"
         "  fi\n"
         "  case ${COMP_WORDS[1]} in\n" +
         cases +
         "  esac\n"
         "  if [ -n \"$valued\" ] && [[ \"|$valued|\" == *\"|$prev|\"* ]]; then\n"
         "    COMPREPLY=($(compgen -f -- \"$cur\"))\n"
         "  elif [[ $cur == -* ]]; then\n"
         "    COMPREPLY=($(compgen -W \"$options\" -- \"$cur\"))\n"
         "  else\n"
         "    COMPREPLY=($(compgen -f -- \"$cur\"))\n"
         "  fi\n"
         "}\n"
         "complete -o filenames -F _hmp hmp\n";
}

}  // namespace hmp::cli
