// YAML -> CNode, with the guard pre-pass, overrides and emission.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/text.hpp>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <sstream>

namespace fp::host {

std::string Mark::str() const {
    // Values from the command line (--set path=value) have no line to point at.
    // They are quoted as an excerpt: a value may hold newlines or escape sequences.
    if (source && (source->rfind("--set ", 0) == 0 || source->rfind("--vary ", 0) == 0))
        return excerpt(*source, 80);
    return (source ? *source : std::string("<input>")) + ":" + std::to_string(line) + ":" +
           std::to_string(col);
}

CNode::CNode() = default;

void refuse_code(CNode& n) {
    n.mark.refuse_code = true;
    for (auto& m : n.key_marks) m.refuse_code = true;
    for (auto& i : n.items) refuse_code(i);
    for (auto& [k, v] : n.keys) refuse_code(v);
}

const CNode* CNode::find(const std::string& key) const {
    for (const auto& [k, v] : keys)
        if (k == key) return &v;
    return nullptr;
}
CNode* CNode::find(const std::string& key) {
    for (auto& [k, v] : keys)
        if (k == key) return &v;
    return nullptr;
}
const Mark* CNode::key_mark(const std::string& key) const {
    for (std::size_t i = 0; i < keys.size(); ++i)
        if (keys[i].first == key) return &key_marks[i];
    return nullptr;
}
// A common slip: an unquoted hex colour, whose '#' starts a comment and swallows the rest of
// the line, so that the error shows up somewhere else.
static const std::string colour_comment_hint =
    " (a '#' after a space starts a comment: quote colours, as in \"#ff6b6b\")";

static bool is_hex_colour_at(const std::string& text, std::size_t hash) {
    if (hash + 7 > text.size()) return false;
    for (std::size_t k = 1; k <= 6; ++k)
        if (!std::isxdigit(static_cast<unsigned char>(text[hash + k]))) return false;
    return true;
}

// Whether `text` has "#rrggbb" right after ':', ',' or '[' and blanks: a linear scan (a regex
// here overflowed the stack on long runs of blanks).
static bool has_unquoted_colour(const std::string& text) {
    for (std::size_t at = text.find('#'); at != std::string::npos; at = text.find('#', at + 1)) {
        if (!is_hex_colour_at(text, at)) continue;
        std::size_t b = at;
        while (b > 0 && std::isspace(static_cast<unsigned char>(text[b - 1]))) --b;
        if (b > 0 && (text[b - 1] == ':' || text[b - 1] == ',' || text[b - 1] == '[')) return true;
    }
    return false;
}

std::string CNode::describe() const {
    switch (type) {
    case Type::Null: return hex_comment ? "nothing" + colour_comment_hint : "nothing";
    case Type::Scalar: return fp::quote(scalar);
    case Type::Sequence: return "a list";
    case Type::Map: return "a mapping";
    }
    return "?";
}

CNode scalar_node(std::string text, bool quoted) {
    CNode n;
    n.type = CNode::Type::Scalar;
    n.scalar = std::move(text);
    n.quoted = quoted;
    return n;
}
CNode map_node() {
    CNode n;
    n.type = CNode::Type::Map;
    return n;
}
CNode seq_node() {
    CNode n;
    n.type = CNode::Type::Sequence;
    return n;
}

namespace {

[[noreturn]] void fail_at(const std::shared_ptr<const std::string>& src, const YAML::Mark& m,
                          const std::string& msg) {
    Mark mk{src, m.line + 1, m.column + 1};
    throw InputError(mk.str() + ": " + msg);
}

// The guard: a pass over the event stream before anything is built.
class Guard : public YAML::EventHandler {
public:
    Guard(std::shared_ptr<const std::string> src, const std::string& text)
        : src_(std::move(src)), text_(text) {}
    int documents = 0;

    void OnDocumentStart(const YAML::Mark& m) override {
        if (++documents > 1) {
            // yaml-cpp 0.7 reports endless empty documents, without moving on, for some
            // invalid text (e.g. a lone ','): that is a syntax error, not a second document.
            if (m.pos == first_.pos && m.pos >= 0 && std::size_t(m.pos) < text_.size())
                fail_at(src_, m,
                        std::string("YAML syntax error: unexpected '") + text_[std::size_t(m.pos)] + "'");
            fail_at(src_, m, "a second YAML document is not supported (one pipeline per file)");
        }
        first_ = m;
    }
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark& m, YAML::anchor_t a) override { value(m, a, nullptr); }
    void OnAlias(const YAML::Mark& m, YAML::anchor_t) override {
        fail_at(src_, m, "YAML aliases are not supported: write the value out");
    }
    void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t a, const std::string& v) override {
        value(m, a, &v);
    }
    void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a,
                         YAML::EmitterStyle::value) override {
        value(m, a, nullptr);
        push(m, false);
    }
    void OnSequenceEnd() override { stack_.pop_back(); }
    void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t a,
                    YAML::EmitterStyle::value) override {
        value(m, a, nullptr);
        push(m, true);
    }
    void OnMapEnd() override { stack_.pop_back(); }

private:
    struct Frame {
        bool map = false;
        bool expect_key = true;
        std::set<std::string> keys;
    };
    void push(const YAML::Mark& m, bool map) {
        if (int(stack_.size()) >= max_yaml_depth)
            fail_at(src_, m, "nesting deeper than " + std::to_string(max_yaml_depth) + " levels");
        Frame f;
        f.map = map;
        stack_.push_back(std::move(f));
    }
    // Called for every node start; checks anchors and map keys.
    void value(const YAML::Mark& m, YAML::anchor_t anchor, const std::string* scalar) {
        if (anchor != YAML::NullAnchor)
            fail_at(src_, m, "YAML anchors are not supported: write the value out");
        if (stack_.empty() || !stack_.back().map) return;
        Frame& f = stack_.back();
        if (f.expect_key) {
            if (!scalar) fail_at(src_, m, "mapping keys must be plain names");
            if (!f.keys.insert(*scalar).second) fail_at(src_, m, "duplicate key '" + *scalar + "'");
        }
        f.expect_key = !f.expect_key;
    }

    std::shared_ptr<const std::string> src_;
    const std::string& text_;
    YAML::Mark first_;
    std::vector<Frame> stack_;
};

// Whether the line of the key at `key_pos` reads "key: #rrggbb": its value became a comment.
bool value_is_colour_comment(const std::string& text, int key_pos) {
    if (key_pos < 0) return false;
    const std::size_t end = std::min(text.find('\n', std::size_t(key_pos)), text.size());
    std::size_t at = text.find(':', std::size_t(key_pos));
    if (at == std::string::npos || at >= end) return false;
    ++at;
    while (at < end && (text[at] == ' ' || text[at] == '\t')) ++at;
    return at < end && text[at] == '#' && is_hex_colour_at(text, at);
}

CNode convert(const YAML::Node& n, const std::shared_ptr<const std::string>& src, const std::string& text) {
    CNode c;
    c.mark = Mark{src, n.Mark().line + 1, n.Mark().column + 1};
    switch (n.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null: c.type = CNode::Type::Null; break;
    case YAML::NodeType::Scalar:
        c.type = CNode::Type::Scalar;
        c.scalar = n.Scalar();
        c.quoted = n.Tag() == "!";
        break;
    case YAML::NodeType::Sequence:
        c.type = CNode::Type::Sequence;
        for (const auto& it : n) c.items.push_back(convert(it, src, text));
        break;
    case YAML::NodeType::Map:
        c.type = CNode::Type::Map;
        for (const auto& it : n) {
            c.keys.emplace_back(it.first.Scalar(), convert(it.second, src, text));
            c.key_marks.push_back(Mark{src, it.first.Mark().line + 1, it.first.Mark().column + 1});
            // An empty value ("key:" and nothing) has yaml-cpp's mark of the next token, often on a
            // later line: point at the key instead, and notice "key: #rrggbb".
            CNode& v = c.keys.back().second;
            if (v.type == CNode::Type::Null && v.mark.line != c.key_marks.back().line) {
                v.mark = c.key_marks.back();
                v.hex_comment = value_is_colour_comment(text, it.first.Mark().pos);
            }
        }
        break;
    }
    return c;
}

} // namespace

static std::string comment_hint(const std::string& text) {
    return has_unquoted_colour(text) ? colour_comment_hint : "";
}

CNode parse_yaml(const std::string& text, const std::string& source) {
    auto src = std::make_shared<const std::string>(source);
    if (text.size() > max_yaml_bytes)
        throw InputError(source + ": file too large (" + std::to_string(text.size()) + " bytes; at most " +
                         std::to_string(max_yaml_bytes) + ")");
    // yaml-cpp guesses UTF-16 or UTF-32 from a byte-order mark or from NUL bytes among the first
    // four ("a\0" read as UTF-16): a config is UTF-8, and a NUL byte is in no text of one.
    const auto starts = [&](std::string_view bom) { return text.compare(0, bom.size(), bom) == 0; };
    if (starts("\xff\xfe") || starts("\xfe\xff") || starts(std::string_view("\0\0\xfe\xff", 4)))
        throw InputError(source +
                         ":1:1: the text is UTF-16 or UTF-32: fixpoint reads UTF-8 (save it as UTF-8)");
    if (const auto nul = text.find('\0'); nul != std::string::npos) {
        const auto line = std::count(text.begin(), text.begin() + std::ptrdiff_t(nul), '\n') + 1;
        const auto col =
            nul - (text.rfind('\n', nul) == std::string::npos ? 0 : text.rfind('\n', nul) + 1) + 1;
        throw InputError(source + ":" + std::to_string(line) + ":" + std::to_string(col) +
                         ": a NUL byte: a config is UTF-8 text (UTF-16 and UTF-32 are refused)");
    }
    try {
        {
            std::istringstream in(text);
            YAML::Parser parser(in);
            Guard guard(src, text);
            // Bounded: the guard throws on a second document, so this cannot loop.
            while (parser.HandleNextDocument(guard)) {
            }
        }
        YAML::Node root = YAML::Load(text);
        CNode c = convert(root, src, text);
        if (c.type == CNode::Type::Null) c.mark = Mark{src, 1, 1};
        return c;
    } catch (const YAML::Exception& e) {
        fail_at(src, e.mark, "YAML syntax error: " + e.msg + comment_hint(text));
    } catch (const InputError& e) {
        throw InputError(e.what() + comment_hint(text));
    }
}

CNode load_yaml_file(const std::string& path) { return parse_yaml(read_yaml_text(path), path); }

CNode parse_config(const std::string& text, const std::string& source) {
    CNode root = parse_yaml(text, source);
    if (root.type == CNode::Type::Null)
        root = map_node(), root.mark = Mark{std::make_shared<const std::string>(source), 1, 1};
    return root;
}

std::string read_yaml_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open file");
    std::string text;
    char buf[65536];
    while (in.read(buf, sizeof buf) || in.gcount() > 0) {
        text.append(buf, std::size_t(in.gcount()));
        if (text.size() > max_yaml_bytes)
            throw InputError(path + ": file too large (more than " + std::to_string(max_yaml_bytes) +
                             " bytes)");
    }
    return text;
}

// ------------------------------------------------------------------ overrides
void apply_override(CNode& root, const std::string& assignment, const std::string& flag) {
    const auto eq = assignment.find('=');
    const std::string where = flag + " " + assignment;
    const std::string shown = excerpt(where, 80); // the assignment may be long or hold control characters
    if (eq == std::string::npos || eq == 0) throw InputError(shown + ": expected path.to.param=value");
    CNode value = parse_yaml(assignment.substr(eq + 1), where);
    override_target(root, assignment.substr(0, eq), shown, value.mark) = std::move(value);
}

CNode& override_target(CNode& root, const std::string& path, const std::string& shown, const Mark& made_at) {
    // Split "a.b[2].c" into steps: names and indices.
    struct Step {
        std::string key;
        long index = -1;
    };
    std::vector<Step> steps;
    std::size_t i = 0;
    while (i < path.size()) {
        if (path[i] == '[') {
            const auto close = path.find(']', i);
            if (close == std::string::npos) throw InputError(shown + ": unclosed '[' in path");
            const std::string num = path.substr(i + 1, close - i - 1);
            if (num.empty() || num.find_first_not_of("0123456789") != std::string::npos)
                throw InputError(shown + ": bad index " + quote(num) + " in path");
            long index = 0;
            const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), index);
            if (ec != std::errc() || end != num.data() + num.size() || index > 1000000000)
                throw InputError(shown + ": index " + quote(num) + " is too large");
            steps.push_back({"", index});
            i = close + 1;
            if (i < path.size() && path[i] == '.') ++i;
        } else {
            std::size_t j = i;
            while (j < path.size() && path[j] != '.' && path[j] != '[') ++j;
            if (j == i) throw InputError(shown + ": empty name in path");
            steps.push_back({path.substr(i, j - i)});
            i = j;
            if (i < path.size() && path[i] == '.') ++i;
        }
    }
    CNode* cur = &root;
    std::string walked;
    for (std::size_t s = 0; s < steps.size(); ++s) {
        const bool last = s + 1 == steps.size();
        const Step& st = steps[s];
        if (st.index >= 0) {
            if (!cur->is_seq()) throw InputError(shown + ": " + quote(walked, 80) + " is not a list");
            if (std::size_t(st.index) >= cur->items.size())
                throw InputError(shown + ": index " + std::to_string(st.index) + " out of range (" +
                                 quote(walked, 80) + " has " + std::to_string(cur->items.size()) + " items)");
            cur = &cur->items[std::size_t(st.index)];
            walked += "[" + std::to_string(st.index) + "]";
        } else {
            if (cur->type == CNode::Type::Null) {
                // A mapping made by the override: it stands where the null stood, or (made from
                // nothing) at the override itself, never at an unknown "<input>:0:0".
                const Mark at = cur->mark.source ? cur->mark : made_at;
                *cur = map_node();
                cur->mark = at;
            }
            if (!cur->is_map())
                throw InputError(shown + ": " + quote(walked.empty() ? "<top>" : walked, 80) +
                                 " is not a mapping");
            CNode* next = cur->find(st.key);
            if (!next) {
                if (!last && steps[s + 1].index >= 0)
                    throw InputError(shown + ": " + quote(walked + (walked.empty() ? "" : ".") + st.key, 80) +
                                     " does not exist");
                cur->keys.emplace_back(st.key, CNode{});
                cur->key_marks.push_back(made_at);
                next = &cur->keys.back().second;
            }
            cur = next;
            walked += (walked.empty() ? "" : ".") + st.key;
        }
    }
    return *cur;
}

// ------------------------------------------------------------------ emission
namespace {
// Block style, except short lists of scalars (they read best on one line); everything in flow
// style below a node with `flow`.
void emit(YAML::Emitter& out, const CNode& n, bool flow) {
    switch (n.type) {
    case CNode::Type::Null: out << YAML::Null; break;
    case CNode::Type::Scalar:
        if (n.quoted)
            out << YAML::DoubleQuoted << n.scalar;
        else
            out << n.scalar;
        break;
    case CNode::Type::Sequence: {
        bool flat = true;
        for (const auto& it : n.items) flat = flat && it.is_scalar();
        if (flow || flat) out << YAML::Flow;
        out << YAML::BeginSeq;
        for (const auto& it : n.items) emit(out, it, flow);
        out << YAML::EndSeq;
        break;
    }
    case CNode::Type::Map:
        if (flow) out << YAML::Flow;
        out << YAML::BeginMap;
        for (const auto& [k, v] : n.keys) {
            out << YAML::Key << k << YAML::Value;
            emit(out, v, flow);
        }
        out << YAML::EndMap;
        break;
    }
}
} // namespace

std::string emit_yaml(const CNode& n) {
    YAML::Emitter out;
    emit(out, n, false);
    return std::string(out.c_str()) + "\n";
}

std::string emit_flow_yaml(const CNode& n) {
    YAML::Emitter out;
    emit(out, n, true);
    return out.c_str();
}

} // namespace fp::host
