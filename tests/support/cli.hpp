// Run the fixpoint CLI as a user would, and capture what it prints.
#pragma once

#include <string>
#include <vector>

namespace fp::test {

struct CliResult {
    int rc = -1;
    std::string out, err;
};

/// Run build/bin/fixpoint with `args`, feeding `input` on stdin.
CliResult run_cli(const std::vector<std::string>& args, const std::string& input = "");

/// A fresh empty folder under the build tree for one test.
std::string scratch_dir(const std::string& name);

/// Write `text` to `path`.
void write_file(const std::string& path, const std::string& text);
std::string read_file(const std::string& path);

/// Bad input as a user meets it: write `yaml` to bad.yaml in a fresh scratch folder `name`, run
/// the CLI there with `args`, and check (gtest) that it exits with 2, prints exactly one line on
/// stderr and leaves nothing behind but bad.yaml. Returns that line without its newline.
std::string run_bad_input(const std::string& name, const std::string& yaml,
                          const std::vector<std::string>& args = {"render", "--quiet", "bad.yaml", "-o",
                                                                  "out.png"});

/// `s` with the first `from` replaced by `to`; throws when `from` is not in `s` (a test setup bug).
std::string replace_once(std::string s, const std::string& from, const std::string& to);

/// The source tree's configs/ folder and tests/ folder.
std::string source_dir();

} // namespace fp::test
