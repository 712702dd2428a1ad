// The command line of every tool of the body scan packages (CLI11): --help, errors that name the
// option, exit status 2 for a usage error. Header-only; tools only (the core libraries never
// parse arguments).
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace body_scan_driver::tools {

// Number checks whose errors read "--width: must be > 0, got -3" (CLI11's Range prints its
// bounds with six decimals, PositiveNumber's upper bound as 309 digits).
inline CLI::Validator inRange(double low, double high, bool open_low = false) {
  std::ostringstream bounds;
  bounds << (open_low ? "> " : ">= ") << low;
  if (high < std::numeric_limits<double>::max()) bounds << " and <= " << high;
  const std::string rule = bounds.str();
  return CLI::Validator(
      [low, high, open_low, rule](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return "must be a number, got '" + text + "'";
        const bool above = open_low ? value > low : value >= low;
        return above && value <= high ? std::string() : "must be " + rule + ", got " + text;
      },
      rule);
}
inline CLI::Validator atLeast(double low) {
  return inRange(low, std::numeric_limits<double>::max());
}
inline CLI::Validator positive() { return inRange(0, std::numeric_limits<double>::max(), true); }

// An option whose value is one of the names in `choices` (help and errors list them): stores the
// value paired with the name given; the default shown is the name of `value`'s initial value.
template <typename T>
CLI::Option* addChoice(CLI::App& app, const std::string& name, T& value,
                       const std::vector<std::pair<std::string, T>>& choices,
                       const std::string& description) {
  std::vector<std::string> names;
  std::string current;
  for (const auto& [choice, choice_value] : choices) {
    names.push_back(choice);
    if (choice_value == value && current.empty()) current = choice;
  }
  CLI::Option* option = app.add_option_function<std::string>(
      name,
      [&value, choices](const std::string& text) {
        for (const auto& [choice, choice_value] : choices)
          if (choice == text) value = choice_value;
      },
      description);
  option->check(CLI::IsMember(names));
  if (!current.empty()) option->default_str(current);
  return option;
}

// Parses argc/argv into `app`. Returns the exit status when the tool should stop: 0 after
// --help, 2 after a usage error (printed with the hint to run --help); nullopt to go on.
// A value given to a flag (`--shape 1`) is reported as such: flags take no value.
inline std::optional<int> parseCommandLine(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
    return std::nullopt;
  } catch (const CLI::ExtrasError& error) {
    const std::vector<std::string> extras = app.remaining(true);
    for (int i = 1; i + 1 < argc; ++i) {
      const std::string name = argv[i];
      const CLI::Option* option =
          name.rfind("--", 0) == 0 ? app.get_option_no_throw(name) : nullptr;
      if (option && option->get_items_expected_max() == 0 &&
          std::find(extras.begin(), extras.end(), argv[i + 1]) != extras.end()) {
        std::cerr << app.get_name() << ": " << name << " is a flag and takes no value: write "
                  << name << ", not " << name << " " << argv[i + 1] << "\nRun with --help for "
                  << "more information.\n";
        return 2;
      }
    }
    return app.exit(error) == 0 ? 0 : 2;
  } catch (const CLI::ParseError& error) {
    return app.exit(error) == 0 ? 0 : 2;
  }
}

}  // namespace body_scan_driver::tools
