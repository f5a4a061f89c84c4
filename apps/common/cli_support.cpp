#include "cli_support.hpp"

#include <algorithm>
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

/// TOML reader that hands CLI11 only the keys of one [section], as top-level items. CLI11 2.1's own
/// section() support passes the section markers on as unknown items, so it cannot be combined with
/// allow_config_extras(error). A section name that belongs to no app is an error (a typo would otherwise
/// silently drop its keys). Scalar values are read here (TOML strings with escapes, '#' inside quotes kept),
/// arrays by CLI11.
class SectionConfig : public CLI::ConfigTOML {
 public:
  explicit SectionConfig(std::string section) : section_(std::move(section)) {}
  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    std::vector<CLI::ConfigItem> result;
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
        continue;
      }
      if (blank_or_comment) continue;
      // A key before any section belongs to no app: it would be silently ignored by every app.
      const auto [key, value] = split_key_value(line.substr(first), line_number);
      if (current.empty()) {
        throw CLI::ConfigError("line " + std::to_string(line_number) + ": key '" + key +
                               "' is outside any section (expected it under [" + section_ + "])");
      }
      if (current != section_) continue;
      key_lines_.emplace(key, line_number);
      if (!value.empty() && value.front() == '[') {
        // An array: CLI11's own reader (no contactnn option takes one today).
        std::istringstream one(key + " = " + value + "\n");
        for (auto& item : CLI::ConfigTOML::from_config(one)) result.push_back(std::move(item));
        continue;
      }
      CLI::ConfigItem item;
      item.name = key;
      item.inputs = {scalar_value(value, line_number)};
      result.push_back(std::move(item));
    }
    return result;
  }

  /// CLI11's writer with values quoted so that the reader above gets them back exactly: strings as TOML
  /// basic strings with escapes (CLI11 2.1 wrote 'a"b' for a value with a double quote, and nothing
  /// readable for one with both quote characters or a line break).
  std::string to_config(const CLI::App* app, bool default_also, bool, std::string) const override {
    std::string out;
    for (const CLI::Option* opt : app->get_options({})) {
      if (!opt->get_configurable()) continue;
      const std::vector<std::string> results = opt->reduced_results();
      std::string value;
      if (results.size() == 1) {
        value = toml_scalar(results.front());
      } else if (results.size() > 1) {
        for (const auto& r : results) value += (value.empty() ? "[" : ",") + toml_scalar(r);
        value += "]";
      } else if (default_also) {
        if (!opt->get_default_str().empty()) {
          value = toml_scalar(opt->get_default_str());
        } else if (opt->get_expected_min() == 0) {
          value = "false";
        }
        // An option with neither a value nor a default (no --input) is left out: CLI11 wrote input="",
        // which read back sets the input to "".
      }
      if (!value.empty()) out += opt->get_single_name() + "=" + value + "\n";
    }
    return out;
  }

  [[nodiscard]] const std::string& section() const { return section_; }
  /// Line of each key of this app's section in the last file read (for messages).
  [[nodiscard]] const std::map<std::string, int>& key_lines() const { return key_lines_; }

 private:
  /// A value as CLI11 writes it when it is a number or a boolean, otherwise a TOML basic string.
  static std::string toml_scalar(const std::string& arg) {
    double number = 0.0;
    const bool bare = arg == "true" || arg == "false" || arg == "nan" || arg == "inf" ||
                      (!arg.empty() && arg.compare(0, 2, "0x") != 0 && arg.compare(0, 2, "0X") != 0 &&
                       arg.find_first_of(" \t\n\r#\"'") == std::string::npos && CLI::detail::lexical_cast(arg, number));
    if (bare) return arg;
    std::string quoted = "\"";
    for (const char c : arg) {
      switch (c) {
        case '"': quoted += "\\\""; break;
        case '\\': quoted += "\\\\"; break;
        case '\n': quoted += "\\n"; break;
        case '\t': quoted += "\\t"; break;
        case '\r': quoted += "\\r"; break;
        default:
          if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
            char escape[8];
            std::snprintf(escape, sizeof escape, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
            quoted += escape;
          } else {
            quoted += c;
          }
      }
    }
    return quoted + "\"";
  }

  [[noreturn]] static void fail(int line_number, const std::string& what) {
    throw CLI::ConfigError("line " + std::to_string(line_number) + ": " + what);
  }

  /// "name = value  # comment" -> {"name", "value  # comment"}; the name unquoted.
  static std::pair<std::string, std::string> split_key_value(const std::string& line, int line_number) {
    const auto equals = line.find('=');
    if (equals == std::string::npos) fail(line_number, "expected 'key = value', found '" + line + "'");
    std::string key = CLI::detail::trim_copy(line.substr(0, equals));
    if (key.size() >= 2 && (key.front() == '"' || key.front() == '\'') && key.back() == key.front()) {
      key = key.substr(1, key.size() - 2);
    }
    if (key.empty()) fail(line_number, "expected 'key = value', found '" + line + "'");
    return {key, CLI::detail::trim_copy(line.substr(equals + 1))};
  }

  /// The value of a TOML scalar: a basic string "..." with escapes (\" \\ \n \t \r \b \f \uXXXX), a
  /// literal string '...', or a bare word (number, true/false), each optionally followed by a # comment.
  /// CLI11 2.1's own reader cuts values at any '#' (a path "run#2.h5" became '"run') and keeps backslashes.
  static std::string scalar_value(const std::string& text, int line_number) {
    std::string value;
    std::size_t pos = 0;
    if (!text.empty() && (text.front() == '"' || text.front() == '\'')) {
      const char quote = text.front();
      for (pos = 1; pos < text.size() && text[pos] != quote; ++pos) {
        if (quote == '"' && text[pos] == '\\' && pos + 1 < text.size()) {
          const char e = text[++pos];
          switch (e) {
            case 'n': value += '\n'; break;
            case 't': value += '\t'; break;
            case 'r': value += '\r'; break;
            case 'b': value += '\b'; break;
            case 'f': value += '\f'; break;
            case '"': case '\\': value += e; break;
            case 'u': {
              const std::string hex = text.substr(pos + 1, 4);
              if (hex.size() != 4 || hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
                fail(line_number, "bad \\u escape in a string");
              }
              const unsigned code = static_cast<unsigned>(std::stoul(hex, nullptr, 16));
              if (code < 0x80) {
                value += static_cast<char>(code);
              } else if (code < 0x800) {
                value += static_cast<char>(0xC0 | (code >> 6));
                value += static_cast<char>(0x80 | (code & 0x3F));
              } else {
                value += static_cast<char>(0xE0 | (code >> 12));
                value += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
                value += static_cast<char>(0x80 | (code & 0x3F));
              }
              pos += 4;
              break;
            }
            default: fail(line_number, std::string("unknown escape '\\") + e + "' in a string");
          }
        } else {
          value += text[pos];
        }
      }
      if (pos >= text.size()) fail(line_number, "unterminated string " + text);
      ++pos;
    } else {
      pos = std::min(text.find('#'), text.size());
      value = CLI::detail::trim_copy(text.substr(0, pos));
      if (value.empty()) fail(line_number, "no value after '=' (an empty string is \"\")");
    }
    const auto rest = text.find_first_not_of(" \t", pos);
    if (rest != std::string::npos && text[rest] != '#') {
      fail(line_number, "unexpected '" + text.substr(rest) + "' after the value");
    }
    return value;
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

std::string parse_config_text(CLI::App& app, const std::string& text) {
  std::istringstream input(text);
  try {
    app.parse_from_stream(input);
  } catch (const CLI::ConfigError& e) {
    return describe_config_error(app, e);
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

std::string effective_config(const CLI::App& app, const std::string& section, const std::vector<std::string>& omit) {
  // config_to_str writes "key=value" lines for every option with a value or default.
  std::string body = app.config_to_str(true, false);
  std::string out = "[" + section + "]\n";
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("config=", 0) == 0 || line.empty()) continue;
    const bool omitted = std::any_of(omit.begin(), omit.end(),
                                     [&](const std::string& key) { return line.rfind(key + "=", 0) == 0; });
    if (!omitted) out += line + "\n";
  }
  return out;
}

void write_effective_config(const CLI::App& app, const std::string& section, const std::filesystem::path& output) {
  std::filesystem::path path = output;
  path += ".config.toml";
  io::write_text_atomically(path, "# effective configuration written by " + app.get_name() + "\n" +
                                      effective_config(app, section));
}

namespace {
CLI::Validator number_at_least(double bound, bool inclusive, const std::string& name) {
  return CLI::Validator(
      [bound, inclusive](std::string& input) -> std::string {
        double value = 0.0;
        if (!io::parse_double(input, value)) return "'" + input + "' is not a number";
        const bool ok = inclusive ? value >= bound : value > bound;
        if (!ok) return std::string("must be ") + (inclusive ? ">= " : "> ") + io::format_double(bound) + ", got " + input;
        return std::string();
      },
      name);
}
}  // namespace

const CLI::Validator kPositive = number_at_least(0.0, false, "POSITIVE");
const CLI::Validator kNonNegative = number_at_least(0.0, true, "NONNEGATIVE");

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
