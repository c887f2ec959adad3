// Edits of a config's YAML text that keep everything else of it: its comments, its layout,
// the order of its keys. The preview page of `fixpoint serve` changes a parameter through
// these (a slider, a colour, a choice of plugin, an item of `maps` added or removed), so that
// the file the user saves is the file they wrote, with that one value changed.
//
// Paths are those of `--set` ("renderer.maps[0].shape.radius"); values are YAML written on
// one line, in flow style ("0.7", "[1, 0]", "{type: circle, radius: 0.5}", "'#ff6b6b'").
// Every function throws fp::InputError "source:line:col: ..." (or "path: ...") for a text
// that does not parse or a path that does not fit its tree, and returns a text that parses
// to the tree the edit describes (tested: parse(result) equals apply_override(parse(text))).
#pragma once

#include <string>

namespace fp::host {

/// `text` with the value at `path` replaced by `value`: a scalar in place, a flow collection
/// in place, a block collection by its lines (written anew at its indentation). A missing
/// last key is added to its mapping in that mapping's style: a line at the keys' indentation
/// after the mapping's last line in a block mapping, ", key: value" before the closing brace
/// of a flow mapping. `source` names the text in messages.
std::string edit_set(const std::string& text, const std::string& source, const std::string& path,
                     const std::string& value);

/// `text` without the item at `path` ("renderer.maps[2]") of a sequence (a block item's
/// lines, or a flow item and its comma).
std::string edit_remove(const std::string& text, const std::string& source, const std::string& path);

/// `text` with `value` appended to the sequence at `path` (a block item at the items'
/// indentation after the last one, or ", value" before a flow sequence's closing bracket).
std::string edit_append(const std::string& text, const std::string& source, const std::string& path,
                        const std::string& value);

} // namespace fp::host
