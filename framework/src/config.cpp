// YAML -> CNode, with the guard pre-pass, overrides and emission.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/config.hpp>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <charconv>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

namespace fp::host {

std::string Mark::str() const {
    // Values from the command line (--set path=value) have no line to point at.
    if (source && (source->rfind("--set ", 0) == 0 || source->rfind("--vary ", 0) == 0)) return *source;
    return (source ? *source : std::string("<input>")) + ":" + std::to_string(line) + ":" +
           std::to_string(col);
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
std::string CNode::describe() const {
    switch (type) {
    case Type::Null: return "nothing";
    case Type::Scalar: return "'" + scalar + "'";
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

CNode convert(const YAML::Node& n, const std::shared_ptr<const std::string>& src) {
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
        for (const auto& it : n) c.items.push_back(convert(it, src));
        break;
    case YAML::NodeType::Map:
        c.type = CNode::Type::Map;
        for (const auto& it : n) {
            c.keys.emplace_back(it.first.Scalar(), convert(it.second, src));
            c.key_marks.push_back(Mark{src, it.first.Mark().line + 1, it.first.Mark().column + 1});
        }
        break;
    }
    return c;
}

} // namespace

// A common slip: an unquoted hex colour, whose '#' starts a comment and swallows the rest of
// the line, so that the error shows up somewhere else.
static std::string comment_hint(const std::string& text) {
    static const std::regex hex_colour(R"([:,\[]\s*#[0-9a-fA-F]{6})");
    return std::regex_search(text, hex_colour)
               ? " (a '#' after a space starts a comment: quote colours, as in \"#ff6b6b\")"
               : "";
}

CNode parse_yaml(const std::string& text, const std::string& source) {
    auto src = std::make_shared<const std::string>(source);
    if (text.size() > max_yaml_bytes)
        throw InputError(source + ": file too large (" + std::to_string(text.size()) + " bytes; at most " +
                         std::to_string(max_yaml_bytes) + ")");
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
        CNode c = convert(root, src);
        if (c.type == CNode::Type::Null) c.mark = Mark{src, 1, 1};
        return c;
    } catch (const YAML::Exception& e) {
        fail_at(src, e.mark, "YAML syntax error: " + e.msg + comment_hint(text));
    } catch (const InputError& e) {
        throw InputError(e.what() + comment_hint(text));
    }
}

CNode load_yaml_file(const std::string& path) {
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
    return parse_yaml(text, path);
}

// ------------------------------------------------------------------ overrides
void apply_override(CNode& root, const std::string& assignment, const std::string& flag) {
    const auto eq = assignment.find('=');
    const std::string where = flag + " " + assignment;
    if (eq == std::string::npos || eq == 0) throw InputError(where + ": expected path.to.param=value");
    const std::string path = assignment.substr(0, eq);
    CNode value = parse_yaml(assignment.substr(eq + 1), where);

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
            if (close == std::string::npos) throw InputError(where + ": unclosed '[' in path");
            const std::string num = path.substr(i + 1, close - i - 1);
            if (num.empty() || num.find_first_not_of("0123456789") != std::string::npos)
                throw InputError(where + ": bad index '" + num + "' in path");
            long index = 0;
            const auto [end, ec] = std::from_chars(num.data(), num.data() + num.size(), index);
            if (ec != std::errc() || end != num.data() + num.size() || index > 1000000000)
                throw InputError(where + ": index '" + num + "' is too large");
            steps.push_back({"", index});
            i = close + 1;
            if (i < path.size() && path[i] == '.') ++i;
        } else {
            std::size_t j = i;
            while (j < path.size() && path[j] != '.' && path[j] != '[') ++j;
            if (j == i) throw InputError(where + ": empty name in path");
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
            if (!cur->is_seq()) throw InputError(where + ": '" + walked + "' is not a list");
            if (std::size_t(st.index) >= cur->items.size())
                throw InputError(where + ": index " + std::to_string(st.index) + " out of range ('" + walked +
                                 "' has " + std::to_string(cur->items.size()) + " items)");
            cur = &cur->items[std::size_t(st.index)];
            walked += "[" + std::to_string(st.index) + "]";
        } else {
            if (cur->type == CNode::Type::Null) *cur = map_node();
            if (!cur->is_map())
                throw InputError(where + ": '" + (walked.empty() ? "<top>" : walked) + "' is not a mapping");
            CNode* next = cur->find(st.key);
            if (!next) {
                if (!last && steps[s + 1].index >= 0)
                    throw InputError(where + ": '" + walked + (walked.empty() ? "" : ".") + st.key +
                                     "' does not exist");
                cur->keys.emplace_back(st.key, CNode{});
                cur->key_marks.push_back(value.mark);
                next = &cur->keys.back().second;
            }
            cur = next;
            walked += (walked.empty() ? "" : ".") + st.key;
        }
    }
    *cur = std::move(value);
}

// ------------------------------------------------------------------ emission
namespace {
void emit(YAML::Emitter& out, const CNode& n) {
    switch (n.type) {
    case CNode::Type::Null: out << YAML::Null; break;
    case CNode::Type::Scalar:
        if (n.quoted)
            out << YAML::DoubleQuoted << n.scalar;
        else
            out << n.scalar;
        break;
    case CNode::Type::Sequence: {
        bool flat = true; // short lists of scalars read best on one line
        for (const auto& it : n.items) flat = flat && it.is_scalar();
        if (flat) out << YAML::Flow;
        out << YAML::BeginSeq;
        for (const auto& it : n.items) emit(out, it);
        out << YAML::EndSeq;
        break;
    }
    case CNode::Type::Map:
        out << YAML::BeginMap;
        for (const auto& [k, v] : n.keys) {
            out << YAML::Key << k << YAML::Value;
            emit(out, v);
        }
        out << YAML::EndMap;
        break;
    }
}
} // namespace

std::string emit_yaml(const CNode& n) {
    YAML::Emitter out;
    emit(out, n);
    return std::string(out.c_str()) + "\n";
}

} // namespace fp::host
