// flam3's XML genomes (.flam3, .flame) as fixpoint configs (docs/flam3.md): the camera, the
// palette, the tone, the finishing, every xform with its variations and the final xform,
// written as a chaos-game recipe with comments saying what came from where.
#pragma once

#include <string>
#include <vector>

namespace fp::host {

/// Which genome of a file of several (`fixpoint import --index K | --name N`).
struct Flam3Select {
    int index = -1;   ///< 0-based; -1: by name, or the first
    std::string name; ///< the flame's name attribute
};

struct Flam3Import {
    std::string yaml;                  ///< the config
    std::vector<std::string> warnings; ///< what could not be carried over, one line each
    int index = 0, count = 0;          ///< the genome taken, of how many
};

/// A file named as a flam3 genome (.flam3, .flame, .flam).
bool is_flam3_file(const std::string& path);

/// The config of one genome of `path`, whose output is `output` (empty: none). A malformed file,
/// an unknown variation or attribute, a value that is not a finite number or out of its range:
/// fp::InputError "PATH:LINE:COL: ..." at the attribute.
Flam3Import import_flam3(const std::string& path, const Flam3Select& which, const std::string& output);

} // namespace fp::host

namespace fp::host {

class Registry;

struct Flam3Export {
    std::string xml;                   ///< the genome file (one flame)
    std::vector<std::string> warnings; ///< what the genome cannot hold, one line each
};

/// The genome of a chaos-game config (flam3_export.cpp; docs/flam3.md): its camera, palette,
/// tone, finishing, and maps (xforms, flam3's variations alone, affine maps) with their weights,
/// colours, opacity and xaos, and the final maps. `sets` are --set overrides. A config the
/// format cannot hold (another renderer, scheme or map) gets fp::InputError at its place.
Flam3Export export_flam3(const Registry& reg, const std::string& config,
                         const std::vector<std::string>& sets);

} // namespace fp::host
