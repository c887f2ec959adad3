// Edits of a config's YAML text that keep the rest of it byte for byte (host/yaml_edit.hpp).
//
// The tree of parse_yaml says where each node starts (its mark); where it ends is read off the
// text by the node's style (a plain or quoted scalar, a flow collection by its brackets, a
// block collection by its indentation). The edit is made on the text, and the result is parsed
// again and compared with the tree the edit describes: a text this surgery cannot handle (a
// plain scalar over several lines, a value that reads differently where it lands) is refused
// with a message, never changed silently.
#include <fixpoint/errors.hpp>
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/yaml_edit.hpp>
#include <fixpoint/text.hpp>

#include <algorithm>
#include <optional>
#include <vector>

namespace fp::host {

namespace {

// The lines of a text and the byte offsets of marks (yaml-cpp counts columns in bytes, after
// a byte-order mark).
class Lines {
public:
    explicit Lines(const std::string& t) : t_(t) {
        starts_.push_back(0);
        for (std::size_t i = 0; i < t.size(); ++i)
            if (t[i] == '\n') starts_.push_back(i + 1);
        if (t.compare(0, 3, "\xef\xbb\xbf") == 0) bom_ = 3;
    }
    const std::string& text() const { return t_; }
    /// The text's line break, for the lines an edit adds.
    std::string eol() const {
        const auto n = t_.find('\n');
        return n != std::string::npos && n > 0 && t_[n - 1] == '\r' ? "\r\n" : "\n";
    }
    int count() const { return int(starts_.size()); }
    std::size_t at(const Mark& m) const {
        const int l = std::clamp(m.line, 1, count()) - 1;
        return std::min(t_.size(),
                        starts_[std::size_t(l)] + (l == 0 ? bom_ : 0) + std::size_t(std::max(m.col, 1) - 1));
    }
    int line_of(std::size_t pos) const {
        return int(std::upper_bound(starts_.begin(), starts_.end(), pos) - starts_.begin()) - 1;
    }
    std::size_t start(int l) const { return starts_[std::size_t(l)]; }
    /// The start of the next line, or the end of the text.
    std::size_t next(int l) const { return l + 1 < count() ? starts_[std::size_t(l + 1)] : t_.size(); }
    /// The end of line `l`'s content: before its '\n' and a '\r'.
    std::size_t end(int l) const {
        std::size_t e = l + 1 < count() ? starts_[std::size_t(l + 1)] - 1 : t_.size();
        if (e > start(l) && t_[e - 1] == '\r') --e;
        return e;
    }
    int indent(int l) const {
        std::size_t p = start(l);
        while (p < t_.size() && t_[p] == ' ') ++p;
        return int(p - start(l));
    }
    /// Blank or a comment only.
    bool empty(int l) const {
        std::size_t p = start(l);
        while (p < end(l) && (t_[p] == ' ' || t_[p] == '\t')) ++p;
        return p == end(l) || t_[p] == '#';
    }
    /// Line `l` holds a block sequence's dash at column `col`.
    bool dash_at(int l, int col) const {
        const std::size_t p = start(l) + std::size_t(col);
        return p < end(l) && t_[p] == '-' && (p + 1 == end(l) || t_[p + 1] == ' ' || t_[p + 1] == '\t');
    }

private:
    const std::string& t_;
    std::vector<std::size_t> starts_;
    std::size_t bom_ = 0;
};

bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// Whether the quote at `i` opens a quoted scalar (not an apostrophe inside a plain one).
bool opens_quote(const std::string& t, std::size_t i) {
    return i == 0 || blank(t[i - 1]) || t[i - 1] == '[' || t[i - 1] == '{' || t[i - 1] == ',' ||
           t[i - 1] == ':';
}

// Just past the closing quote of the quoted scalar opening at `p` ('' escapes ' in single
// quotes, a backslash escapes in double quotes).
std::size_t quoted_end(const std::string& t, std::size_t p) {
    const char q = t[p];
    for (std::size_t i = p + 1; i < t.size(); ++i) {
        if (q == '"' && t[i] == '\\') {
            ++i;
        } else if (t[i] == q) {
            if (q == '\'' && i + 1 < t.size() && t[i + 1] == '\'')
                ++i;
            else
                return i + 1;
        }
    }
    return t.size();
}

// A '#' that starts a comment: at a line's start or after a blank.
bool comment_at(const std::string& t, std::size_t i) { return t[i] == '#' && (i == 0 || blank(t[i - 1])); }

// The end of a plain scalar starting at `p`: the end of its line, a comment, or (in a flow
// collection) the indicator that ends it; trailing blanks excluded.
std::size_t plain_end(const std::string& t, std::size_t p, bool flow) {
    std::size_t last = p;
    for (std::size_t i = p; i < t.size() && t[i] != '\n'; ++i) {
        if (i > p && comment_at(t, i)) break;
        if (flow && (t[i] == ',' || t[i] == ']' || t[i] == '}')) break;
        if (!blank(t[i])) last = i + 1;
    }
    return last;
}

// Just past the bracket closing the flow collection opening at `p`.
std::size_t flow_end(const std::string& t, std::size_t p) {
    int depth = 0;
    for (std::size_t i = p; i < t.size(); ++i) {
        const char c = t[i];
        if (c == '[' || c == '{') {
            ++depth;
        } else if (c == ']' || c == '}') {
            if (--depth == 0) return i + 1;
        } else if ((c == '\'' || c == '"') && opens_quote(t, i)) {
            i = quoted_end(t, i) - 1;
        } else if (comment_at(t, i)) {
            while (i + 1 < t.size() && t[i + 1] != '\n') ++i;
        }
    }
    return t.size();
}

// The end of the last line of the block collection starting at `p`: the lines after it that
// are more indented (for a sequence, also its dashes at its own indentation), blank and
// comment lines inside kept, those after its last line left out.
std::size_t block_end(const Lines& L, std::size_t p, bool seq) {
    const int first = L.line_of(p), col = int(p - L.start(first));
    int last = first;
    for (int l = first + 1; l < L.count(); ++l) {
        if (L.empty(l)) continue;
        const int ind = L.indent(l);
        if (ind < col || (seq && ind == col && !L.dash_at(l, col))) break;
        last = l;
    }
    return L.end(last);
}

// The end of a block scalar ('|' or '>' at `p`): the lines more indented than its owner's.
std::size_t block_scalar_end(const Lines& L, std::size_t p) {
    const int first = L.line_of(p), owner = L.indent(first);
    int last = first;
    for (int l = first + 1; l < L.count(); ++l) {
        if (L.start(l) == L.end(l) || L.indent(l) == int(L.end(l) - L.start(l))) continue;
        if (L.indent(l) <= owner) break;
        last = l;
    }
    return L.end(last);
}

bool is_flow_at(const Lines& L, const CNode& n) {
    const std::size_t p = L.at(n.mark);
    return p < L.text().size() && (L.text()[p] == '[' || L.text()[p] == '{');
}

struct Span {
    std::size_t begin = 0, end = 0;
};

// Where node `n` stands in the text; `flow`: it is inside a flow collection.
Span extent(const Lines& L, const CNode& n, bool flow) {
    const std::string& t = L.text();
    const std::size_t p = L.at(n.mark);
    const char c = p < t.size() ? t[p] : '\0';
    if (n.is_map() || n.is_seq())
        return {p, c == '[' || c == '{' ? flow_end(t, p) : block_end(L, p, n.is_seq())};
    if (c == '\'' || c == '"') return {p, quoted_end(t, p)};
    if (!flow && n.is_scalar() && n.quoted && (c == '|' || c == '>')) return {p, block_scalar_end(L, p)};
    return {p, plain_end(t, p, flow)};
}

// The ':' after the key standing at `key`.
std::size_t key_colon(const Lines& L, const Mark& key) {
    const std::string& t = L.text();
    std::size_t p = L.at(key);
    if (p < t.size() && (t[p] == '\'' || t[p] == '"')) p = quoted_end(t, p);
    for (; p < t.size(); ++p)
        if (t[p] == ':' && (p + 1 == t.size() || blank(t[p + 1]) || t[p + 1] == ',' || t[p + 1] == '}'))
            return p;
    return t.size();
}

// The end of what follows position `p` on its line before a comment (and the blanks before it).
std::size_t before_comment(const Lines& L, std::size_t p) {
    const std::string& t = L.text();
    const std::size_t e = L.end(L.line_of(p));
    std::size_t i = p;
    while (i < e && !comment_at(t, i)) ++i;
    while (i > p && blank(t[i - 1])) --i;
    return i;
}

struct Edit {
    std::size_t begin, end;
    std::string text;
};

// The text with `edits` made (back to front); a text whose extents were misread (edits out
// of order) is refused like one that would read differently.
std::string apply(std::string t, std::vector<Edit> edits, const std::string& path) {
    std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin > b.begin; });
    std::size_t limit = t.size();
    for (const Edit& e : edits) {
        if (e.begin > e.end || e.end > limit)
            throw InputError(path +
                             ": cannot edit this text in place (its layout is not one this edit reads)");
        t.replace(e.begin, e.end - e.begin, e.text);
        limit = e.begin;
    }
    return t;
}

// One step of a path: a key or an index.
struct Hop {
    std::string key;
    long index = -1;
};

// The hops from `n` to the node at address `target`.
bool hops_to(const CNode& n, const CNode* target, std::vector<Hop>& out) {
    if (&n == target) return true;
    for (const auto& [k, v] : n.keys) {
        out.push_back({k, -1});
        if (hops_to(v, target, out)) return true;
        out.pop_back();
    }
    for (std::size_t i = 0; i < n.items.size(); ++i) {
        out.push_back({"", long(i)});
        if (hops_to(n.items[i], target, out)) return true;
        out.pop_back();
    }
    return false;
}

// A node of the original tree on the way to the target, with what the text needs to know.
struct Place {
    const CNode* node = nullptr;
    const CNode* parent = nullptr;
    const Mark* key = nullptr; ///< its key's mark when its parent is a mapping
    bool flow = false;         ///< inside a flow collection
};

// The path's nodes that exist in `root` (root first), and the names after the last of them
// that the edit adds. The path is read by override_target, on a copy, so that the paths of
// edits are exactly those of --set.
struct Located {
    std::vector<Place> places;
    std::vector<std::string> missing;
    std::vector<Hop> hops; ///< all of them, from the root
};

Located locate(const CNode& root, const std::string& path) {
    if (path.empty()) throw InputError("empty path (expected one like renderer.width)");
    CNode copy = root;
    const CNode& target = override_target(copy, path, path, Mark{});
    Located loc;
    hops_to(copy, &target, loc.hops);
    loc.places.push_back({&root, nullptr, nullptr, false});
    for (const Hop& h : loc.hops) {
        const Place& up = loc.places.back();
        const CNode& n = *up.node;
        if (!loc.missing.empty() || !(h.index >= 0 ? n.is_seq() : n.find(h.key) != nullptr)) {
            loc.missing.push_back(h.key);
            continue;
        }
        Place p;
        p.parent = &n;
        p.node = h.index >= 0 ? &n.items[std::size_t(h.index)] : n.find(h.key);
        p.key = h.index >= 0 ? nullptr : n.key_mark(h.key);
        loc.places.push_back(p);
    }
    return loc;
}

// Marks which places stand inside flow collections (needs the text).
void mark_flow(const Lines& L, Located& loc) {
    for (std::size_t i = 1; i < loc.places.size(); ++i) {
        const Place& up = loc.places[i - 1];
        loc.places[i].flow = up.flow || is_flow_at(L, *up.node);
    }
}

std::string spaces(std::size_t n) { return std::string(n, ' '); }

// `value` (parsed as `v`, a mapping or a list written in flow style) as the lines of a block
// collection, the first at the place of the one it replaces and the others at `indent`:
// "key: value" or "- item", each entry's text as written in `value`. Empty when `value` does
// not split so (an entry without a value).
std::string block_lines(const std::string& value, const CNode& v, std::size_t indent,
                        const std::string& eol) {
    const Lines L(value);
    std::vector<std::string> entries;
    for (std::size_t i = 0; i < v.keys.size(); ++i) {
        const CNode& x = v.keys[i].second;
        if (x.type == CNode::Type::Null) return "";
        const std::size_t b = L.at(v.key_marks[i]), e = extent(L, x, true).end;
        entries.push_back(value.substr(b, e - b));
    }
    for (const CNode& x : v.items) {
        if (x.type == CNode::Type::Null) return "";
        const Span s = extent(L, x, true);
        entries.push_back("- " + value.substr(s.begin, s.end - s.begin));
    }
    std::string out;
    for (std::size_t i = 0; i < entries.size(); ++i) out += (i ? eol + spaces(indent) : "") + entries[i];
    return out;
}

// The edits that write `value` (parsed as `v`) in place of the node at `p`.
std::vector<Edit> replace(const Lines& L, const Place& p, const std::string& value, const CNode& v) {
    const CNode& n = *p.node;
    // "key:" with nothing after it (or "key: #rrggbb", an unquoted colour read as a comment):
    // the value goes after the colon, a comment after it stays.
    if (n.type == CNode::Type::Null && p.key &&
        ((n.mark.line == p.key->line && n.mark.col == p.key->col) || n.hex_comment)) {
        const std::size_t colon = key_colon(L, *p.key);
        const std::size_t end = n.hex_comment ? L.end(L.line_of(colon)) : before_comment(L, colon + 1);
        return {{colon + 1, end, " " + value}};
    }
    const Span s = extent(L, n, p.flow);
    const bool block = (n.is_map() || n.is_seq()) && !is_flow_at(L, n);
    if (!block) return {{s.begin, s.end, value}};
    // A block collection: written anew as one of its style when the value is one...
    const std::size_t col = s.begin - L.start(L.line_of(s.begin));
    if ((n.is_map() && v.is_map() && !v.keys.empty()) || (n.is_seq() && v.is_seq() && !v.items.empty())) {
        const std::string lines = block_lines(value, v, col, L.eol());
        if (!lines.empty()) return {{s.begin, s.end, lines}};
    }
    // ... else the value follows its key on the key's line ("iteration: {type: mann}"), or
    // stands in its place when the collection starts on its key's or its dash's line.
    if (p.key && L.line_of(s.begin) > L.line_of(L.at(*p.key))) {
        const std::size_t colon = key_colon(L, *p.key);
        return {{colon + 1, before_comment(L, colon + 1), " " + value},
                {L.start(L.line_of(s.begin)), L.next(L.line_of(s.end)), ""}};
    }
    return {{s.begin, s.end, value}};
}

// The edit that adds `key: value` to the mapping at `p`.
Edit add_key(const Lines& L, const Place& p, const std::string& key, const std::string& value) {
    const std::string& t = L.text();
    const CNode& n = *p.node;
    if (n.type == CNode::Type::Null) { // the whole text is empty (or comments)
        const bool newline = !t.empty() && t.back() != '\n';
        return {t.size(), t.size(), (newline ? L.eol() : "") + key + ": " + value + L.eol()};
    }
    const Span s = extent(L, n, p.flow);
    if (is_flow_at(L, n)) {
        std::size_t at = s.end - 1; // the closing brace
        while (at > s.begin && blank(t[at - 1])) --at;
        const char before = t[at - 1];
        return {at, at, (before == '{' ? "" : before == ',' ? " " : ", ") + key + ": " + value};
    }
    const std::size_t col = s.begin - L.start(L.line_of(s.begin));
    return {s.end, s.end, L.eol() + spaces(col) + key + ": " + value};
}

// The value of an edit, parsed; a message naming the path when it is not one line of YAML.
CNode parse_value(const std::string& path, const std::string& value) {
    if (value.find_first_of("\r\n") != std::string::npos)
        throw InputError(path + ": the value must be one line of YAML, got " + quote(value));
    try {
        return parse_yaml(value, "value");
    } catch (const InputError& e) {
        throw InputError(path + ": " + e.what());
    }
}

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// The same tree: what emit_yaml writes of each is the same text (compared here without
// writing it, which takes longer than the parse).
bool same(const CNode& a, const CNode& b) {
    if (a.type != b.type || a.scalar != b.scalar || a.quoted != b.quoted ||
        a.items.size() != b.items.size() || a.keys.size() != b.keys.size())
        return false;
    for (std::size_t i = 0; i < a.items.size(); ++i)
        if (!same(a.items[i], b.items[i])) return false;
    for (std::size_t i = 0; i < a.keys.size(); ++i)
        if (a.keys[i].first != b.keys[i].first || !same(a.keys[i].second, b.keys[i].second)) return false;
    return true;
}

// The result must read back as the tree the edit describes: else the edit is refused.
void check(const std::string& out, const std::string& source, const CNode& expected, const std::string& path,
           const std::string& what) {
    bool ok = false;
    try {
        ok = same(parse_yaml(out, source), expected);
    } catch (const InputError&) {
        ok = false;
    }
    if (!ok)
        throw InputError(path + ": cannot " + what + " in place: the text would read differently" +
                         (what.rfind("remove", 0) == 0 ? "" : " (quote the value?)"));
}

CNode& walk(CNode& root, const std::vector<Hop>& hops, std::size_t n) {
    CNode* cur = &root;
    for (std::size_t i = 0; i < n; ++i)
        cur = hops[i].index >= 0 ? &cur->items[std::size_t(hops[i].index)] : cur->find(hops[i].key);
    return *cur;
}

} // namespace

std::string edit_set(const std::string& text, const std::string& source, const std::string& path,
                     const std::string& value_text) {
    const CNode root = parse_yaml(text, source);
    const std::string value = trim(value_text);
    const CNode v = parse_value(path, value);
    Located loc = locate(root, path);
    const Lines L(text);
    mark_flow(L, loc);
    const Place& deepest = loc.places.back();
    std::vector<Edit> edits;
    if (loc.missing.empty()) {
        edits = replace(L, deepest, value, v);
    } else {
        // The names the path adds, as flow mappings around the value: "a: {b: value}".
        std::string nested = value;
        for (std::size_t i = loc.missing.size(); i-- > 1;)
            nested = "{" + loc.missing[i] + ": " + nested + "}";
        if (deepest.node->is_map() || !deepest.parent)
            edits = {add_key(L, deepest, loc.missing[0], nested)};
        else
            edits = replace(L, deepest, "{" + loc.missing[0] + ": " + nested + "}", parse_value(path, "{}"));
    }
    std::string out = apply(text, edits, path);
    CNode expected = root;
    override_target(expected, path, path, v.mark) = v;
    check(out, source, expected, path, "write " + quote(value));
    return out;
}

std::string edit_remove(const std::string& text, const std::string& source, const std::string& path) {
    const CNode root = parse_yaml(text, source);
    Located loc = locate(root, path);
    if (!loc.missing.empty() || loc.hops.back().index < 0)
        throw InputError(path + ": not an item of a list (remove takes a path like renderer.maps[2])");
    const Lines L(text);
    mark_flow(L, loc);
    const Place& item = loc.places.back();
    const Place& list = loc.places[loc.places.size() - 2];
    const CNode& seq = *list.node;
    const std::size_t i = std::size_t(loc.hops.back().index), n = seq.items.size();
    std::vector<Edit> edits;
    if (n == 1) {
        edits = replace(L, list, "[]", parse_value(path, "[]"));
    } else if (is_flow_at(L, seq)) {
        // The item and the comma after it; the last item, with the comma before it.
        const auto span = [&](std::size_t k) { return extent(L, seq.items[k], true); };
        edits = {i + 1 < n ? Edit{span(i).begin, span(i + 1).begin, ""}
                           : Edit{span(i - 1).end, span(i).end, ""}};
    } else {
        // The item's lines, from its dash to its last line.
        const std::string& t = L.text();
        std::size_t dash = L.at(item.node->mark);
        while (dash > 0 && t[dash] != '-') --dash;
        const int first = L.line_of(dash), last = L.line_of(extent(L, *item.node, false).end);
        edits = {{L.start(first), L.next(last), ""}};
    }
    std::string out = apply(text, edits, path);
    CNode expected = root;
    CNode& s = walk(expected, loc.hops, loc.hops.size() - 1);
    s.items.erase(s.items.begin() + long(i));
    check(out, source, expected, path, "remove the item");
    return out;
}

std::string edit_append(const std::string& text, const std::string& source, const std::string& path,
                        const std::string& value_text) {
    const CNode root = parse_yaml(text, source);
    const std::string value = trim(value_text);
    const CNode v = parse_value(path, value);
    Located loc = locate(root, path);
    // Nothing there yet: the list is made with the value in it.
    if (!loc.missing.empty() || loc.places.back().node->type == CNode::Type::Null)
        return edit_set(text, source, path, "[" + value + "]");
    const Lines L(text);
    mark_flow(L, loc);
    const Place& list = loc.places.back();
    const CNode& seq = *list.node;
    if (!seq.is_seq()) throw InputError(path + ": " + quote(path, 80) + " is not a list");
    const std::string& t = L.text();
    const Span s = extent(L, seq, list.flow);
    Edit e;
    if (is_flow_at(L, seq)) {
        std::size_t at = s.end - 1; // the closing bracket
        while (at > s.begin && blank(t[at - 1])) --at;
        const char before = t[at - 1];
        e = {at, at, (before == '[' ? "" : before == ',' ? " " : ", ") + value};
    } else {
        // A new item at the items' indentation; a mapping written as the last item is (in
        // block style, its keys lined up with that item's).
        const std::size_t col = s.begin - L.start(L.line_of(s.begin));
        std::string item = "- " + value;
        const CNode& last = seq.items.back();
        if (v.is_map() && !v.keys.empty() && last.is_map() && !is_flow_at(L, last)) {
            const std::size_t at = L.at(last.mark), key_col = at - L.start(L.line_of(at));
            const std::string lines = key_col > col + 1 ? block_lines(value, v, key_col, L.eol()) : "";
            if (!lines.empty()) item = "-" + spaces(key_col - col - 1) + lines;
        }
        e = {s.end, s.end, L.eol() + spaces(col) + item};
    }
    std::string out = apply(text, {e}, path);
    CNode expected = root;
    walk(expected, loc.hops, loc.hops.size()).items.push_back(v);
    check(out, source, expected, path, "append " + quote(value));
    return out;
}

} // namespace fp::host
