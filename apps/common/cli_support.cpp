#include "cli_support.hpp"

#include <cctype>
#include <cstdio>
#include <map>
#include <optional>
#include <iostream>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "io/csv.hpp"

namespace contactnn::cli {

namespace {

/// The sections a contactnn study config may hold: one per app.
const std::set<std::string> kKnownSections = {"gen-configs", "train-net", "evaluate-net"};

/// TOML reader that hands CLI11 only the lines of one [section], as top-level keys. CLI11 2.1's own
/// section() support passes the section markers on as unknown items, so it cannot be combined with
/// allow_config_extras(error). A section name that belongs to no app is an error (a typo would otherwise
/// silently drop its keys).
class SectionConfig : public CLI::ConfigTOML {
 public:
  explicit SectionConfig(std::string section) : section_(std::move(section)) {}
  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    std::ostringstream kept;
    std::string line;
    std::string current;
    int line_number = 0;
    key_lines_.clear();
    while (std::getline(input, line)) {
      ++line_number;
      const auto first = line.find_first_not_of(" \t");
      const bool blank_or_comment = first == std::string::npos || line[first] == '#' || line[first] == ';';
      if (!blank_or_comment && line[first] == '[') {
        const auto close = line.find(']', first);
        const auto after = close == std::string::npos ? close : line.find_first_not_of(" \t", close + 1);
        if (close == std::string::npos || (after != std::string::npos && line[after] != '#')) {
          throw CLI::ConfigError("line " + std::to_string(line_number) + ": malformed section header '" +
                                 line.substr(first) + "' (expected '[name]')");
        }
        current = line.substr(first + 1, close - first - 1);
        if (kKnownSections.count(current) == 0) {
          throw CLI::ConfigError("line " + std::to_string(line_number) + ": unknown section [" + current +
                                 "] (expected one of [gen-configs], [train-net], [evaluate-net])");
        }
        kept << "\n";
        continue;
      }
      if (!blank_or_comment) {
        // A key before any section belongs to no app: it would be silently ignored by every app.
        const std::string key = key_of(line.substr(first));
        if (current.empty()) {
          throw CLI::ConfigError("line " + std::to_string(line_number) + ": key '" + key +
                                 "' is outside any section (expected it under [" + section_ + "])");
        }
        if (current == section_) key_lines_.emplace(key, line_number);
      }
      // Lines outside this app's section become blank, so CLI11's line count still matches the file.
      kept << (current == section_ ? line : std::string()) << "\n";
    }
    std::istringstream filtered(kept.str());
    return CLI::ConfigTOML::from_config(filtered);
  }

  [[nodiscard]] const std::string& section() const { return section_; }
  /// Line of each key of this app's section in the last file read (for messages).
  [[nodiscard]] const std::map<std::string, int>& key_lines() const { return key_lines_; }

 private:
  /// "name = value" -> "name" (quotes and blanks removed).
  static std::string key_of(const std::string& line) {
    std::string key = line.substr(0, line.find('='));
    while (!key.empty() && (key.back() == ' ' || key.back() == '\t')) key.pop_back();
    if (key.size() >= 2 && (key.front() == '"' || key.front() == '\'') && key.back() == key.front()) {
      key = key.substr(1, key.size() - 2);
    }
    return key;
  }

  std::string section_;
  mutable std::map<std::string, int> key_lines_;
};

/// The config file given with --config ("" if none).
std::string config_file(const CLI::App& app) {
  // The raw value: as<>() would run the option's validators again, and throw if the file is missing.
  const CLI::Option* config = app.get_config_ptr();
  return config != nullptr && !config->results().empty() ? config->results().front() : "";
}

/// True when `argv` sets option `--name` itself (as "--name value" or "--name=value").
bool on_command_line(int argc, char** argv, const std::string& name) {
  const std::string flag = "--" + name;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == flag || arg.rfind(flag + "=", 0) == 0) return true;
  }
  return false;
}

/// The long names of the options a config file may set (for "expected one of" messages).
std::string config_keys(const CLI::App& app) {
  std::string keys;
  for (const CLI::Option* option : app.get_options()) {
    if (option->get_lnames().empty() || !option->get_configurable()) continue;
    const std::string& name = option->get_lnames().front();
    if (name == "help" || name == "config") continue;
    keys += (keys.empty() ? "" : ", ") + name;
  }
  return keys;
}

/// For a parse error caused by a value in the config file (its option named in the message and not given on
/// the command line): "config file 'F', line N, key 'k'". std::nullopt otherwise.
std::optional<std::string> config_origin(const CLI::App& app, int argc, char** argv, const std::string& message) {
  const auto formatter = std::dynamic_pointer_cast<SectionConfig>(app.get_config_formatter());
  if (formatter == nullptr || config_file(app).empty()) return std::nullopt;
  for (const auto& [key, line] : formatter->key_lines()) {
    const auto at = message.find("--" + key);
    if (at == std::string::npos) continue;
    const auto end = at + 2 + key.size();
    const bool whole_name = end == message.size() || !(std::isalnum(static_cast<unsigned char>(message[end])) ||
                                                       message[end] == '_' || message[end] == '-');
    if (!whole_name || on_command_line(argc, argv, key)) continue;
    return "config file '" + config_file(app) + "', line " + std::to_string(line) + ", key '" + key + "'";
  }
  return std::nullopt;
}

/// CLI11 reports an unknown config key as "INI was not able to parse <key>": say what it is and where.
std::string describe_config_error(const CLI::App& app, const CLI::ConfigError& e) {
  const std::string message = e.what();
  const std::string prefix = "INI was not able to parse ";
  const auto formatter = std::dynamic_pointer_cast<SectionConfig>(app.get_config_formatter());
  if (message.rfind(prefix, 0) != 0 || formatter == nullptr) return message;
  const std::string key = message.substr(prefix.size());
  const auto line = formatter->key_lines().find(key);
  return (line != formatter->key_lines().end() ? "line " + std::to_string(line->second) + ": " : std::string()) +
         "unknown key '" + key + "' in [" + formatter->section() + "] (expected one of: " + config_keys(app) + ")";
}

}  // namespace

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ConfigError& e) {
      // CLI11's message names the key but not the file.
      std::cerr << "error: config file '" << config_file(app) << "': " << describe_config_error(app, e) << "\n";
      return static_cast<int>(ExitCode::kUsage);
    } catch (const CLI::ParseError& e) {
      // A value out of range or of the wrong type that came from the config file: say which file and line.
      if (const auto origin = config_origin(app, argc, argv, e.what())) {
        std::cerr << "error: " << *origin << ": " << e.what() << "\n";
        return static_cast<int>(ExitCode::kUsage);
      }
      const int code = app.exit(e);
      return code == 0 ? 0 : static_cast<int>(ExitCode::kUsage);
    }
    return body();
  } catch (const Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::exception& e) {
    std::cerr << "error: internal: " << e.what() << "\n";
    return static_cast<int>(ExitCode::kInternal);
  }
}

void add_config_option(CLI::App& app, const std::string& section) {
  app.set_config("--config", "", "TOML config file; this app reads its [" + section + "] section")
      ->check(CLI::ExistingFile);
  app.config_formatter(std::make_shared<SectionConfig>(section));
  app.allow_config_extras(CLI::config_extras_mode::error);
  // Options added after this record their defaults, so the effective config (and --help) shows the value
  // each option really has, and the written config can be fed back with --config.
  app.option_defaults()->always_capture_default();
}

std::string effective_config(const CLI::App& app, const std::string& section) {
  // config_to_str writes "key=value" lines for every option with a value or default.
  std::string body = app.config_to_str(true, false);
  std::string out = "[" + section + "]\n";
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    // An empty value ("") is an option without a value (e.g. no --input): writing it back would set it to "".
    const bool unset = line.size() >= 3 && line.compare(line.size() - 3, 3, "=\"\"") == 0;
    if (line.rfind("config=", 0) == 0 || line.empty() || unset) continue;
    out += line + "\n";
  }
  return out;
}

void write_effective_config(const CLI::App& app, const std::string& section, const std::filesystem::path& output) {
  std::filesystem::path path = output;
  path += ".config.toml";
  io::write_text_atomically(path, "# effective configuration written by " + app.get_name() + "\n" +
                                      effective_config(app, section));
}

void add_exit_code_footer(CLI::App& app) {
  app.footer(
      "Exit codes: 0 success; 1 internal error; 2 bad command line or config (unknown key, value out of range);\n"
      "3 bad input data (malformed CSV, wrong HDF5 schema, shape or file kind); 4 I/O failure; 5 numerical\n"
      "failure (non-finite value where a finite one is required).");
}

Progress::Progress(std::string label, bool quiet)
    : label_(std::move(label)), quiet_(quiet), start_(std::chrono::steady_clock::now()) {}

void Progress::update(std::int64_t done, std::int64_t total) {
  if (quiet_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0 ? static_cast<double>(done) / elapsed : 0.0;
  const double eta = rate > 0 ? static_cast<double>(total - done) / rate : 0.0;
  std::fprintf(stderr, "\r%s: %lld / %lld (%.1f%%), %.0f/s, elapsed %.1f s, ETA %.1f s   ", label_.c_str(),
               static_cast<long long>(done), static_cast<long long>(total),
               total > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 100.0, rate, elapsed, eta);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::finish() {
  if (printed_ && !quiet_) std::fprintf(stderr, "\n");
  printed_ = false;
}

}  // namespace contactnn::cli
