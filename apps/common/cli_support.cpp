#include "cli_support.hpp"

#include <omp.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "io/csv.hpp"
#include "io/inp_deck.hpp"
#include "io/interrupt_cleanup.hpp"

namespace contactnn::cli {

namespace {

/// The sections a contactnn study config may hold: one per app.
const std::set<std::string> kKnownSections = {"gen-configs", "train-net", "evaluate-net", "scene-study",
                                              "replay"};

/// How an option's value is typed in TOML, from CLI11's type name ("INT:INT in [1 - 400]" -> integer).
enum class ValueKind { kBoolean, kInteger, kReal, kText };

ValueKind value_kind(const CLI::Option& option) {
  if (option.get_expected_min() == 0) return ValueKind::kBoolean;  // a flag
  std::string type = option.get_type_name();
  type = type.substr(0, type.find(':'));
  if (type == "BOOLEAN") return ValueKind::kBoolean;
  if (type == "INT" || type == "UINT") return ValueKind::kInteger;
  if (type == "FLOAT") return ValueKind::kReal;
  return ValueKind::kText;
}

std::string kind_text(ValueKind kind) {
  switch (kind) {
    case ValueKind::kBoolean: return "a boolean (true or false)";
    case ValueKind::kInteger: return "an integer";
    case ValueKind::kReal: return "a number";
    case ValueKind::kText: return "a string";
  }
  return "a value";
}

std::string node_text(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a floating-point number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

/// The shortest text that reads back to `value`; TOML spells the non-finite ones inf, -inf and nan.
std::string real_text(double value) {
  if (std::isnan(value)) return "nan";
  return io::format_double(value);
}

/// A value as a TOML basic string, escaped.
std::string toml_string(const std::string& text) {
  std::string quoted = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': quoted += "\\\""; break;
      case '\\': quoted += "\\\\"; break;
      case '\n': quoted += "\\n"; break;
      case '\t': quoted += "\\t"; break;
      case '\r': quoted += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char escape[8];
          std::snprintf(escape, sizeof escape, "\\u%04x",
                        static_cast<unsigned>(static_cast<unsigned char>(c)));
          quoted += escape;
        } else {
          quoted += c;
        }
    }
  }
  return quoted + "\"";
}

/// An option's value (a CLI11 result or default string) as TOML of the option's type.
std::string toml_value(const CLI::Option& option, const std::string& text) {
  switch (value_kind(option)) {
    case ValueKind::kBoolean: {
      std::string lower = text;
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char c) { return std::tolower(c); });
      if (lower == "true" || lower == "1" || lower == "on" || lower == "yes") return "true";
      if (lower == "false" || lower == "0" || lower == "off" || lower == "no") return "false";
      break;
    }
    case ValueKind::kInteger: {
      std::int64_t value = 0;
      if (CLI::detail::lexical_cast(text, value)) return std::to_string(value);
      std::uint64_t big = 0;
      if (CLI::detail::lexical_cast(text, big)) return std::to_string(big);
      break;
    }
    case ValueKind::kReal: {
      double value = 0.0;
      // Respelled in one canonical form (".5" is not TOML, "1E-13" would come back as "1e-13"), so the
      // text read back writes the same text again.
      if (CLI::detail::lexical_cast(text, value)) return real_text(value);
      break;
    }
    case ValueKind::kText: break;
  }
  return toml_string(text);
}

/// "line N, key 'k': what": a message about one key (cli::run prints it after "config file 'F', ").
[[noreturn]] void key_error(std::int64_t line, const std::string& key, const std::string& what) {
  throw CLI::ConfigError("line " + std::to_string(line) + ", key '" + key + "': " + what);
}

[[noreturn]] void line_error(std::int64_t line, const std::string& what) {
  const bool column = what.rfind("column ", 0) == 0;
  throw CLI::ConfigError("line " + std::to_string(line) + (column ? ", " : ": ") + what);
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

/// Reads a TOML 1.0 document with toml++ and hands CLI11 the keys of one [section] as top-level items, each
/// value checked against its option's type and turned into the text CLI11 converts. The sections of the
/// other apps are skipped; anything else at the top level is an error (a typo would silently drop keys).
class SectionConfig : public CLI::Config {
 public:
  SectionConfig(std::string section, const CLI::App* app) : section_(std::move(section)), app_(app) {}

  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    key_lines_.clear();
    const std::string text{std::istreambuf_iterator<char>(input), std::istreambuf_iterator<char>()};
    toml::table root;
    try {
      root = toml::parse(text);
    } catch (const toml::parse_error& e) {
      line_error(e.source().begin.line, "column " + std::to_string(e.source().begin.column) +
                                            ": not valid TOML: " + std::string(e.description()));
    }
    // toml++ keeps keys sorted; report problems in file order.
    const auto by_line = [](const toml::table& table) {
      std::vector<std::pair<std::string, const toml::node*>> entries;
      for (const auto& [key, node] : table) entries.emplace_back(std::string(key.str()), &node);
      std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
        return a.second->source().begin.line < b.second->source().begin.line;
      });
      return entries;
    };
    std::vector<CLI::ConfigItem> result;
    for (const auto& [name, node] : by_line(root)) {
      const std::int64_t line = node->source().begin.line;
      if (!node->is_table()) {
        if (node->is_array_of_tables()) {
          line_error(line, "[[" + name + "]] is an array of tables (expected one [" + name + "] section)");
        }
        line_error(line, "key '" + name + "' is outside any section (expected it under [" + section_ + "])");
      }
      if (kKnownSections.count(name) == 0) {
        line_error(
            line,
            "unknown section [" + name +
                "] (expected one of [gen-configs], [train-net], [evaluate-net], [scene-study], [replay])");
      }
      if (name != section_) continue;
      for (const auto& [key, value] : by_line(*node->as_table())) {
        result.push_back(item(key, *value));
      }
    }
    return result;
  }

  std::string to_config(const CLI::App* app, bool default_also, bool, std::string) const override {
    std::string out;
    for (const CLI::Option* opt : app->get_options({})) {
      if (!opt->get_configurable() || opt->get_lnames().empty() || opt->get_lnames().front() == "config")
        continue;
      const std::vector<std::string> results = opt->reduced_results();
      std::string value;
      if (opt->get_expected_max() > 1) {
        // A repeatable option (evaluate-net's --weights, --data, --pairs): every value, as a TOML array (the
        // first alone read back as one network); none given, nothing (written as "[]", it read back as a file
        // named "[]").
        for (const std::string& r : results) value += (value.empty() ? "[" : ", ") + toml_value(*opt, r);
        if (!value.empty()) value += "]";
      } else if (!results.empty()) {
        value = toml_value(*opt, results.front());
      } else if (!opt->get_needs().empty()) {
        // Not given, and only valid with another option (evaluate-net's --newton-steps needs --input): its
        // default, written, would read back as given without it.
      } else if (default_also) {
        if (!opt->get_default_str().empty()) {
          value = toml_value(*opt, opt->get_default_str());
        } else if (opt->get_expected_min() == 0) {
          value = "false";
        }
        // An option with neither a value nor a default (no --input) is left out: written as input = "",
        // it would read back as an input named "".
      }
      if (!value.empty()) out += opt->get_single_name() + "=" + value + "\n";
    }
    return out;
  }

  [[nodiscard]] const std::string& section() const { return section_; }
  /// Line of each key of this app's section in the last file read (for messages).
  [[nodiscard]] const std::map<std::string, std::int64_t>& key_lines() const { return key_lines_; }

 private:
  /// One key of the section as a CLI11 item, its TOML type checked against the option's.
  CLI::ConfigItem item(const std::string& key, const toml::node& value) const {
    const std::int64_t line = value.source().begin.line;
    key_lines_.emplace(key, line);
    const CLI::Option* option = app_->get_option_no_throw("--" + key);
    if (option == nullptr || !option->get_configurable() || key == "config" || key == "help") {
      line_error(line, "unknown key '" + key + "' in [" + section_ +
                           "] (expected one of: " + config_keys(*app_) + ")");
    }
    const ValueKind kind = value_kind(*option);
    std::string text;
    bool fits = false;
    if (const auto* b = value.as_boolean()) {
      fits = kind == ValueKind::kBoolean;
      text = b->get() ? "true" : "false";
    } else if (const auto* i = value.as_integer()) {
      // An integer is also a fine real ("xy_limit = 2") and path-like text ("hidden = 8"); 0 and 1 are
      // booleans as the effective configs of earlier versions wrote them ("restore_best=1").
      const bool zero_or_one = i->get() == 0 || i->get() == 1;
      fits = kind == ValueKind::kInteger || kind == ValueKind::kReal || kind == ValueKind::kText ||
             (kind == ValueKind::kBoolean && zero_or_one);
      text = kind == ValueKind::kBoolean ? (i->get() == 1 ? "true" : "false") : std::to_string(i->get());
    } else if (const auto* f = value.as_floating_point()) {
      fits = kind == ValueKind::kReal;
      text = real_text(f->get());
    } else if (const auto* s = value.as_string()) {
      fits = kind == ValueKind::kText;
      text = s->get();
    }
    std::vector<std::string> inputs = {text};
    if (const auto* array = value.as_array(); array != nullptr && option->get_expected_max() > 1) {
      // A repeatable option: an array of its values (each checked as a single value is).
      inputs.clear();
      fits = true;
      for (const toml::node& element : *array) {
        const auto* s = element.as_string();
        if (kind != ValueKind::kText || s == nullptr) {
          key_error(line, key, "expected an array of strings, got an element that is " + node_text(element));
        }
        inputs.push_back(s->get());
      }
    }
    if (!fits) key_error(line, key, "expected " + kind_text(kind) + ", got " + node_text(value));
    CLI::ConfigItem item;
    item.name = key;
    item.inputs = std::move(inputs);
    return item;
  }

  std::string section_;
  const CLI::App* app_;
  mutable std::map<std::string, std::int64_t> key_lines_;
};

/// True when `argv` sets option `--name` itself (as "--name value" or "--name=value").
bool on_command_line(int argc, char** argv, const std::string& name) {
  const std::string flag = "--" + name;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == flag || arg.rfind(flag + "=", 0) == 0) return true;
  }
  return false;
}

/// For a parse error caused by a value in the config file (its option named in the message and not given on
/// the command line): "config file 'F', line N, key 'k'". std::nullopt otherwise.
std::optional<std::string> config_origin(const CLI::App& app, int argc, char** argv,
                                         const std::string& message) {
  const auto formatter = std::dynamic_pointer_cast<SectionConfig>(app.get_config_formatter());
  if (formatter == nullptr || config_path(app).empty()) return std::nullopt;
  for (const auto& [key, line] : formatter->key_lines()) {
    const auto at = message.find("--" + key);
    if (at == std::string::npos) continue;
    const auto end = at + 2 + key.size();
    const bool whole_name =
        end == message.size() || !(std::isalnum(static_cast<unsigned char>(message[end])) ||
                                   message[end] == '_' || message[end] == '-');
    if (!whole_name || on_command_line(argc, argv, key)) continue;
    return "config file '" + config_path(app).string() + "', line " + std::to_string(line) + ", key '" + key +
           "'";
  }
  return std::nullopt;
}

/// The message of a config error, for after "config file 'F'": ", line N, key 'k': ..." for an error about
/// one key, ": ..." otherwise. CLI11's own unknown-key message ("INI was not able to parse k") cannot occur
/// (SectionConfig checks keys first) but is translated all the same.
std::string describe_config_error(const CLI::App& app, const CLI::ConfigError& e) {
  const std::string message = e.what();
  if (message.rfind("line ", 0) == 0 && message.find(", key '") != std::string::npos &&
      message.find(", key '") < message.find(':')) {
    return ", " + message;
  }
  const std::string prefix = "INI was not able to parse ";
  if (message.rfind(prefix, 0) == 0) {
    const auto formatter = std::dynamic_pointer_cast<SectionConfig>(app.get_config_formatter());
    const std::string section = formatter != nullptr ? formatter->section() : "?";
    return ": unknown key '" + message.substr(prefix.size()) + "' in [" + section +
           "] (expected one of: " + config_keys(app) + ")";
  }
  return ": " + message;
}

/// Installed before main: a signal that arrives while the app is still building its options finds the
/// handler already in place (nothing to clean up yet, and the documented exit code all the same).
const bool g_interrupt_cleanup_installed = [] {
  io::install_interrupt_cleanup();
  return true;
}();

}  // namespace

int cap_openmp_threads() {
  const int asked = omp_get_max_threads();
  if (asked <= kMaxThreads) return asked;
  std::fprintf(stderr,
               "warning: OpenMP's default of %d threads (OMP_NUM_THREADS) is more than %lld; using %lld\n",
               asked, static_cast<long long>(kMaxThreads), static_cast<long long>(kMaxThreads));
  omp_set_num_threads(static_cast<int>(kMaxThreads));
  return static_cast<int>(kMaxThreads);
}

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  (void)g_interrupt_cleanup_installed;
  (void)cap_openmp_threads();
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ConfigError& e) {
      std::cerr << "error: config file '" << config_path(app).string() << "'" << describe_config_error(app, e)
                << "\n";
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
  } catch (const InvalidArgument& e) {
    // An option's value refused after parsing (--hidden '8,0'), which came from the config file: say where.
    if (const auto origin = config_origin(app, argc, argv, e.what())) {
      std::cerr << "error: " << *origin << ": " << e.what() << "\n";
    } else {
      std::cerr << "error: " << e.what() << "\n";
    }
    return e.exit_code();
  } catch (const Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return e.exit_code();
  } catch (const std::bad_alloc&) {
    // Not a bug but a resource the system refused, like a full disk: same code, and the temporaries are
    // gone (their owners' destructors ran while the exception came up).
    std::cerr
        << "error: out of memory: the system refused an allocation (free memory, use fewer --threads, or "
           "give a smaller input)\n";
    return static_cast<int>(ExitCode::kIo);
  } catch (const std::exception& e) {
    std::cerr << "error: internal: " << e.what() << "\n";
    return static_cast<int>(ExitCode::kInternal);
  }
}

void add_config_option(CLI::App& app, const std::string& section) {
  app.set_config("--config", "", "TOML config file; this app reads its [" + section + "] section")
      ->check(CLI::ExistingFile);
  app.config_formatter(std::make_shared<SectionConfig>(section, &app));
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
    std::string message = describe_config_error(app, e);
    return message.substr(message.find_first_not_of(",: "));
  } catch (const CLI::ParseError& e) {
    return e.what();
  }
  return "";
}

std::filesystem::path config_path(const CLI::App& app) {
  // The raw value: as<>() would run the option's validators again, and throw if the file is missing.
  const CLI::Option* config = app.get_config_ptr();
  return config != nullptr && !config->results().empty() ? config->results().front() : "";
}

std::string effective_config(const CLI::App& app, const std::string& section,
                             const std::vector<std::string>& omit) {
  std::string body = app.config_to_str(true, false);
  std::string out = "[" + section + "]\n";
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty()) continue;
    const bool omitted = std::any_of(omit.begin(), omit.end(),
                                     [&](const std::string& key) { return line.rfind(key + "=", 0) == 0; });
    if (!omitted) out += line + "\n";
  }
  return out;
}

namespace {
/// A TOML value as the text CLI11 is given for it, numbers through double (2 and 2.0 agree; hidden = 8 and
/// hidden = "8", as earlier versions and this one write a text option, agree too).
std::string comparable(const toml::node& node) {
  if (const auto* i = node.as_integer()) return real_text(static_cast<double>(i->get()));
  if (const auto* f = node.as_floating_point()) return real_text(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "1" : "0";  // earlier versions wrote 1 for true
  if (const auto* s = node.as_string()) return s->get();
  std::ostringstream out;
  out << node_text(node);
  return out.str();
}

/// key -> comparable value of every key of every table in `text`.
std::map<std::string, std::string> settings(const std::string& text) {
  std::map<std::string, std::string> result;
  const toml::table root = toml::parse(text);
  for (const auto& [section, table] : root) {
    if (const auto* t = table.as_table()) {
      for (const auto& [key, value] : *t) result[std::string(key.str())] = comparable(value);
    }
  }
  return result;
}
}  // namespace

std::string config_differences(const std::string& a, const std::string& b,
                               const std::vector<std::string>& ignore) {
  std::map<std::string, std::string> first, second;
  try {
    first = settings(a);
    second = settings(b);
  } catch (const toml::parse_error&) {
    return a == b ? "" : "  (the texts differ and are not both TOML)\n";
  }
  for (const std::string& key : ignore) {
    first.erase(key);
    second.erase(key);
  }
  std::set<std::string> keys;
  for (const auto& [k, v] : first) keys.insert(k);
  for (const auto& [k, v] : second) keys.insert(k);
  std::string out;
  for (const std::string& key : keys) {
    const auto x = first.find(key);
    const auto y = second.find(key);
    const std::string vx = x != first.end() ? x->second : "(absent)";
    const std::string vy = y != second.end() ? y->second : "(absent)";
    if (vx != vy) out += "  " + key + ": " + vx + " vs " + vy + "\n";
  }
  return out;
}

std::filesystem::path effective_config_path(const std::filesystem::path& output) {
  std::filesystem::path path = output;
  path += ".config.toml";
  return path;
}

std::unique_ptr<io::AtomicOutput> write_effective_config(const CLI::App& app, const std::string& section,
                                                         const std::filesystem::path& output) {
  if (io::written_in_place(output)) return nullptr;
  return io::write_text_uncommitted(
      effective_config_path(output),
      "# effective configuration written by " + app.get_name() + "\n" + effective_config(app, section));
}

namespace {
CLI::Validator number_at_least(double bound, bool inclusive, const std::string& name) {
  return CLI::Validator(
      [bound, inclusive](std::string& input) -> std::string {
        double value = 0.0;
        const std::string relation = std::string(inclusive ? ">= " : "> ") + io::format_double(bound);
        if (!io::parse_double(input, value)) return "'" + input + "' is not a number";
        const bool ok = std::isfinite(value) && (inclusive ? value >= bound : value > bound);
        if (!ok) return "must be a finite number " + relation + ", got " + input;
        return std::string();
      },
      name);
}
}  // namespace

const CLI::Validator kPositive = number_at_least(0.0, false, "POSITIVE");
const CLI::Validator kNonNegative = number_at_least(0.0, true, "NONNEGATIVE");

CLI::Validator real_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& input) -> std::string {
        double value = 0.0;
        if (!io::parse_double(input, value)) return "'" + input + "' is not a number";
        if (!(std::isfinite(value) && value >= lo && value <= hi)) {
          return "must be a finite number in " + io::format_double(lo) + ".." + io::format_double(hi) +
                 ", got " + input;
        }
        return std::string();
      },
      "FLOAT in [" + io::format_double(lo) + " - " + io::format_double(hi) + "]");
}

CLI::Validator integer_in(std::int64_t lo, std::int64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& input) -> std::string {
        std::string_view text = input;
        while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
        while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
        if (!text.empty() && text.front() == '+') text.remove_prefix(1);
        std::int64_t value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        const bool whole = !text.empty() && end == text.data() + text.size();
        if (!whole || ec != std::errc() || value < lo || value > hi) {
          return "must be an integer in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " +
                 io::quote_text(input);
        }
        input = std::to_string(value);  // what CLI11 converts: decimal, never octal or hexadecimal
        return std::string();
      },
      "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

void warn_about_raw_output(const char* tools, const std::string& input, const std::string& output,
                           const std::vector<std::string>& replaced, std::size_t rows) {
  for (const auto& name : replaced) {
    std::fprintf(stderr, "warning: input column '%s' is replaced by %s own '%s' column\n", name.c_str(),
                 tools, name.c_str());
  }
  if (rows == 0) {
    std::fprintf(stderr, "warning: '%s' has a header and no data rows: '%s' has the header only\n",
                 input.c_str(), output.c_str());
  }
}

void add_exit_code_footer(CLI::App& app) {
  app.footer(
      "Exit codes: 0 success; 1 internal error; 2 bad command line or config (unknown key, value out of "
      "range,\n"
      "an output that is an input); 3 bad input data (malformed CSV, wrong HDF5 schema, shape or file kind, "
      "corrupt\n"
      "file); 4 I/O or resource failure (cannot open, write or rename; disk full; out of memory); 5 "
      "numerical\n"
      "failure (non-finite value where a finite one is required); 128+N killed by signal N after removing\n"
      "its temporary files (130 SIGINT, 143 SIGTERM).");
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
               total > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 100.0, rate,
               elapsed, eta);
  std::fflush(stderr);
  printed_ = true;
}

void Progress::finish() {
  if (printed_ && !quiet_) std::fprintf(stderr, "\n");
  printed_ = false;
}

std::vector<std::string> warn_unapplied_geometry(const char* tool, const std::string& deck) {
  std::vector<std::string> keywords = io::unapplied_geometry_keywords(deck);
  for (const std::string& k : keywords) {
    std::fprintf(
        stderr,
        "%s: warning: %s: this keyword changes the contact geometry CalculiX uses, and it is not applied "
        "here: the gaps and points are those of the mesh as written\n",
        tool, k.c_str());
  }
  return keywords;
}

std::vector<int> integer_list(const std::string& text, int lo, int hi, const std::string& expected) {
  std::vector<int> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    std::size_t used = 0;
    int n = 0;
    try {
      n = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    CONTACTNN_REQUIRE_AS(InvalidArgument, !item.empty() && used == item.size() && n >= lo && n <= hi,
                         expected << ", got " << io::quote_text(text));
    values.push_back(n);
  }
  return values;
}

std::string join_command_line(int argc, char** argv) {
  std::string out;
  for (int i = 0; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg.find_first_of(" \t\"'$\\") != std::string::npos) {
      std::string quoted = "'";
      for (const char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      arg = quoted + "'";
    }
    out += (i > 0 ? " " : "") + arg;
  }
  return out;
}

}  // namespace contactnn::cli
