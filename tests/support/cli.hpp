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

/// The source tree's configs/ folder and tests/ folder.
std::string source_dir();

} // namespace fp::test
