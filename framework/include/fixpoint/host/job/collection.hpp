// A collection (`fixpoint render --vary PATH=V1,V2,...`): one render per value, each written to
// its own file, and a contact sheet of them all with a caption per child.
#pragma once

#include <fixpoint/host/core/registry.hpp>
#include <fixpoint/host/job/render_job.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace fp::host {

/// --vary PATH=V1,V2,... or PATH=A..B (whole numbers): the path and the values, split at
/// top-level commas; at most 1000. fp::InputError otherwise.
std::pair<std::string, std::vector<std::string>> parse_vary(const std::string& spec);

/// The file of child k (from 1) beside the sheet: out.png -> out-3.png.
std::string child_path(const std::string& sheet, std::size_t k);

struct CollectionRequest {
    std::string config;            ///< the config file (or image) rendered
    std::vector<std::string> sets; ///< --set, before the --vary value
    std::string vary;              ///< --vary
    int columns = 0;               ///< of the contact sheet (0: about square)
    bool allow_code = false;       ///< --allow-python
    bool draft = false;            ///< --draft: every child a draft
    /// The sheet's file and how it may be written (output, force, draft_name; default_file),
    /// the threads: each child is planned with these, its file beside the sheet.
    RenderRequest sheet;
    bool validate_only = false; ///< check everything, render nothing
    /// Where summary lines (info) and warnings (without "warning: ") go, one line each.
    std::function<void(const std::string&)> info, warn;
};

/// Checks every child (its config, memory, file) and the whole collection's memory before the
/// first render; under mpirun child k renders whole on rank k mod N and rank 0 writes. Every
/// file or none is written (a failing child, a full disk, a Ctrl-C). fp::InputError for bad input,
/// fp::Cancelled when `hooks.cancel` is set.
void run_collection(const Registry& reg, const CollectionRequest& req, const RenderHooks& hooks);

} // namespace fp::host
