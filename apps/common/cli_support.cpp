#include "cli_support.hpp"

#include <cstdio>
#include <iostream>
#include <set>
#include <sstream>

#include "core/error.hpp"
#include "io/csv.hpp"

namespace contactnn::cli {

int run(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    try {
      app.parse(argc, argv);
    } catch (const CLI::ConfigError& e) {
      // CLI11's message names the key but not the file.
      const CLI::Option* config = app.get_config_ptr();
      const std::string file = config != nullptr && config->count() > 0 ? config->as<std::string>() : "";
      std::cerr << "error: config file '" << file << "': " << e.what() << "\n";
      return static_cast<int>(ExitCode::kUsage);
    } catch (const CLI::ParseError& e) {
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
    while (std::getline(input, line)) {
      ++line_number;
      const auto first = line.find_first_not_of(" \t");
      if (first != std::string::npos && line[first] == '[') {
        const auto close = line.find(']', first);
        current = line.substr(first + 1, close == std::string::npos ? std::string::npos : close - first - 1);
        if (kKnownSections.count(current) == 0) {
          throw CLI::ConfigError("line " + std::to_string(line_number) + ": unknown section [" + current +
                                 "] (expected one of [gen-configs], [train-net], [evaluate-net])");
        }
        kept << "\n";
        continue;
      }
      // Lines outside this app's section become blank, so CLI11's line count still matches the file.
      kept << (current == section_ ? line : std::string()) << "\n";
    }
    std::istringstream filtered(kept.str());
    return CLI::ConfigTOML::from_config(filtered);
  }

 private:
  std::string section_;
};

}  // namespace

void add_config_option(CLI::App& app, const std::string& section) {
  app.set_config("--config", "", "TOML config file; this app reads its [" + section + "] section")
      ->check(CLI::ExistingFile);
  app.config_formatter(std::make_shared<SectionConfig>(section));
  app.allow_config_extras(CLI::config_extras_mode::error);
}

std::string effective_config(const CLI::App& app, const std::string& section) {
  // config_to_str writes "key=value" lines for every option with a value or default.
  std::string body = app.config_to_str(true, false);
  std::string out = "[" + section + "]\n";
  std::istringstream lines(body);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("config=", 0) == 0 || line.empty()) continue;
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
