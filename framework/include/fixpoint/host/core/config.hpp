// Stage 1 of loading a pipeline: YAML text -> a tree of nodes that remember their position.
//
// yaml-cpp 0.7 accepts duplicate keys (first wins), aliases and many documents, and loops
// forever on some inputs through LoadAll; so every text first goes through a guard over the
// event stream (size, depth, aliases/anchors, a second document, duplicate keys), then
// through YAML::Load, and is copied into CNode, which later stages read (never yaml-cpp's
// nodes, whose non-const operator[] mutates them).
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace fp::host {

/// A position in a source text, 1-based.
struct Mark {
    std::shared_ptr<const std::string> source;
    int line = 0, col = 0;
    /// Read from a recipe embedded in an image (a file from anywhere) without --allow-python:
    /// a plugin that runs code (python-scheme) is refused here (validate).
    bool refuse_code = false;
    std::string str() const; ///< "file:line:col"
};

struct CNode {
    enum class Type { Null, Scalar, Sequence, Map };
    Type type = Type::Null;
    std::string scalar;       ///< Scalar: the text
    bool quoted = false;      ///< Scalar: written in quotes (never a number, bool or null)
    bool hex_comment = false; ///< Null: its line ends in a comment like "#ff6b6b" (an unquoted colour)
    std::vector<CNode> items; ///< Sequence
    std::vector<std::pair<std::string, CNode>> keys; ///< Map, in file order
    std::vector<Mark> key_marks;                     ///< Map: where each key stands
    Mark mark;

    // Declared here, defined where CNode is complete: clang with libstdc++ 12 refuses the
    // implicit constructor of a class holding std::pair<std::string, CNode> while the class
    // is still incomplete.
    CNode();

    bool is_map() const { return type == Type::Map; }
    bool is_seq() const { return type == Type::Sequence; }
    bool is_scalar() const { return type == Type::Scalar; }
    const CNode* find(const std::string& key) const;
    CNode* find(const std::string& key);
    const Mark* key_mark(const std::string& key) const;
    /// Short description for messages: "a mapping", "a list", "'abc'" (an escaped excerpt).
    std::string describe() const;
};

/// Largest YAML text accepted, and deepest nesting.
constexpr std::size_t max_yaml_bytes = 4u << 20;
constexpr int max_yaml_depth = 64;

/// Parse YAML text named `source` (used in marks). Throws fp::InputError "source:l:c: msg".
CNode parse_yaml(const std::string& text, const std::string& source);
/// parse_yaml of a config: an empty text is an empty mapping at 1:1 (so that the message is
/// about the missing renderer, not about a null document).
CNode parse_config(const std::string& text, const std::string& source);
/// Read and parse a file (size checked first).
CNode load_yaml_file(const std::string& path);
/// A file's text, refused (fp::InputError "path: ...") when it cannot be read or is larger
/// than max_yaml_bytes.
std::string read_yaml_text(const std::string& path);

/// Mark every node of `root` as read from an image's recipe that may not run code
/// (Mark::refuse_code).
void refuse_code(CNode& root);

/// Apply `path.to.param=value` (value is YAML) to `root`. Throws fp::InputError.
/// `flag` names the option in messages (--set, --vary).
void apply_override(CNode& root, const std::string& assignment, const std::string& flag = "--set");
/// The node at `path` ("a.b[2].c") in `root`, as apply_override finds it: a missing name is
/// added (null) to its mapping, and what is made stands at `made_at`. Throws fp::InputError
/// "shown: why" for a path that does not fit the tree (a missing index, a scalar on the way).
CNode& override_target(CNode& root, const std::string& path, const std::string& shown, const Mark& made_at);

/// Emit as block YAML (keys in stored order).
std::string emit_yaml(const CNode& n);
/// Emit as flow YAML on one line ("[1, 0]", "{type: circle, radius: 1}", "\"#ff6b6b\"").
std::string emit_flow_yaml(const CNode& n);

/// Build nodes programmatically (for resolved recipes).
CNode scalar_node(std::string text, bool quoted = false);
CNode map_node();
CNode seq_node();

} // namespace fp::host
