#include "io/files/json_reader.h"

#include "io/files/input_file.h"

#include <cmath>
#include <memory>
#include <set>
#include <sstream>

namespace softtouch::io {
namespace {

std::string describe(const nlohmann::json& v) {
    std::string s = v.dump();
    if (s.size() > 40)
        s = s.substr(0, 37) + "...";
    return s;
}

std::string formatNumber(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

/// Line and column (from 1) of a byte offset.
std::pair<std::size_t, std::size_t> lineAndColumn(std::string_view text, std::size_t offset) {
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return {line, column};
}

/// What a scan of the text finds before anything is parsed: the first bracket that opens level
/// kMaxJsonDepth + 1, and how many keys and values the document holds (brackets, colons and commas
/// inside strings aside). A scan, not a parse: it only has to be right for text the parser would accept.
struct JsonShape {
    std::optional<std::size_t> tooDeepAt;
    std::size_t keys = 0;    ///< Object members (colons).
    std::size_t values = 0;  ///< Array elements and members, about (commas and openings).
};

JsonShape scanShape(std::string_view text) {
    JsonShape shape;
    int depth = 0;
    bool inString = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (c == '\\')
                ++i;
            else if (c == '"')
                inString = false;
        } else if (c == '"') {
            inString = true;
        } else if (c == '[' || c == '{') {
            ++shape.values;
            if (++depth > kMaxJsonDepth && !shape.tooDeepAt)
                shape.tooDeepAt = i;
        } else if (c == ']' || c == '}') {
            --depth;
        } else if (c == ':') {
            ++shape.keys;
        } else if (c == ',') {
            ++shape.values;
        }
    }
    return shape;
}

/// A parser callback that keeps every value and records keys that appear twice in one object (JSON
/// allows it, nlohmann keeps the last; a hand-edited file that says "mass" twice means one of them).
nlohmann::json::parser_callback_t duplicateKeyFinder(std::vector<std::string>& duplicates) {
    auto open = std::make_shared<std::vector<std::set<std::string>>>();
    return [open, &duplicates](int, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        if (event == Event::object_start)
            open->emplace_back();
        else if (event == Event::object_end && !open->empty())
            open->pop_back();
        else if (event == Event::key && !open->empty() && !open->back().insert(parsed.get<std::string>()).second)
            duplicates.push_back(parsed.get<std::string>());
        return true;
    };
}

}  // namespace

void JsonIssues::add(const std::string& pointer, const std::string& problem) {
    addGeneral((pointer.empty() ? "/" : pointer) + ": " + problem);
}

void JsonIssues::addGeneral(const std::string& problem) {
    // A file of a million unknown keys must not become a million messages: the first kMaxListed are
    // listed, then one line says how many more there were.
    if (m_messages.size() < kMaxListed) {
        m_messages.push_back(m_file + ": " + problem);
        return;
    }
    ++m_unlisted;
    const std::string more = m_file + ": (" + std::to_string(m_unlisted) + " more problems not listed)";
    if (m_messages.size() == kMaxListed)
        m_messages.push_back(more);
    else
        m_messages.back() = more;
}

std::string JsonIssues::summary() const {
    if (m_messages.empty())
        return {};
    std::string s = m_messages.front();
    if (m_messages.size() > 1)
        s += " (and " + std::to_string(m_messages.size() - 1) + " more problem" + (m_messages.size() > 2 ? "s" : "") +
             "; 'softtouch-cli validate' lists them all)";
    return s;
}

std::optional<nlohmann::json> parseJsonFile(const std::string& path, JsonIssues& issues) {
    auto read = readInputFile(path, kMaxJsonFileBytes);
    if (!read) {
        issues.addGeneral(read.message());
        return std::nullopt;
    }
    return parseJsonText(read.value(), issues);
}

std::optional<nlohmann::json> parseJsonText(std::string_view text, JsonIssues& issues) {
    const JsonShape shape = scanShape(text);
    if (shape.tooDeepAt) {
        const auto [line, column] = lineAndColumn(text, *shape.tooDeepAt);
        issues.addGeneral("at line " + std::to_string(line) + ", column " + std::to_string(column) +
                          ": arrays and objects nest deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        return std::nullopt;
    }
    // Refused before parsing: a parsed key costs ~100 bytes and a value 16 or more, so a file under the
    // size limit could still ask for gigabytes (5 million keys in 66 MB took 2.7 GB).
    if (shape.keys > kMaxJsonKeys || shape.values > kMaxJsonValues) {
        const bool keys = shape.keys > kMaxJsonKeys;
        issues.addGeneral("holds " + std::to_string(keys ? shape.keys : shape.values) + (keys ? " keys" : " values") +
                          ", more than the " + std::to_string(keys ? kMaxJsonKeys : kMaxJsonValues) +
                          " SoftTouch reads in one file (its largest files, painted maps of a 64x64x64 lattice or an "
                          "hour of device recording, hold far fewer keys and a fraction of the values)");
        return std::nullopt;
    }
    std::vector<std::string> duplicates;
    try {
        nlohmann::json doc = nlohmann::json::parse(text, duplicateKeyFinder(duplicates));
        if (!duplicates.empty()) {
            for (const std::string& key : duplicates)
                issues.addGeneral("the key \"" + key + "\" appears twice in one object (the second would silently replace the first)");
            return std::nullopt;
        }
        return doc;
    } catch (const nlohmann::json::parse_error& e) {
        const auto [line, column] = lineAndColumn(text, e.byte > 0 ? e.byte - 1 : 0);
        std::string what = e.what();
        if (const auto pos = what.find("syntax error"); pos != std::string::npos)
            what = what.substr(pos);
        issues.addGeneral("invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column) + ": " +
                          what);
    } catch (const nlohmann::json::exception& e) {
        // out_of_range 406: a number beyond double's range ("1e400"), which has no position of its own.
        std::string what = e.what();
        if (const auto pos = what.find("] "); pos != std::string::npos)
            what = what.substr(pos + 2);
        issues.addGeneral("invalid JSON: " + what);
    }
    return std::nullopt;
}

JsonValue JsonValue::operator[](const char* key) const {
    const nlohmann::json* child = nullptr;
    if (isObject()) {
        if (auto it = m_value->find(key); it != m_value->end())
            child = &*it;
    }
    return JsonValue(child, m_pointer + "/" + key, m_issues);
}

JsonValue JsonValue::at(std::size_t i) const {
    const nlohmann::json* child = (isArray() && i < m_value->size()) ? &(*m_value)[i] : nullptr;
    return JsonValue(child, m_pointer + "/" + std::to_string(i), m_issues);
}

void JsonValue::problem(const std::string& what) const { m_issues->add(m_pointer, what); }

void JsonValue::checkKeys(std::initializer_list<const char*> allowed) const {
    if (!isObject())
        return;
    for (auto it = m_value->begin(); it != m_value->end(); ++it) {
        bool known = false;
        for (const char* key : allowed)
            known = known || it.key() == key;
        if (!known) {
            std::string list;
            for (const char* key : allowed)
                list += std::string(list.empty() ? "" : ", ") + key;
            m_issues->add(m_pointer + "/" + it.key(), "unknown field; expected one of: " + list);
        }
    }
}

bool JsonValue::missing(bool required) const {
    if (m_value)
        return false;
    if (required)
        m_issues->add(m_pointer, "missing; this field is required");
    return true;
}

bool JsonValue::expectObject(bool required) const {
    if (missing(required))
        return false;
    if (!m_value->is_object()) {
        problem("expected an object, got " + describe(*m_value));
        return false;
    }
    return true;
}

std::optional<double> JsonValue::number(double lo, double hi, const char* unit, bool required) const {
    if (missing(required))
        return std::nullopt;
    const std::string range = "a number in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]" +
                              (unit && *unit ? std::string(" (") + unit + ")" : std::string());
    if (!m_value->is_number()) {
        problem("expected " + range + ", got " + describe(*m_value));
        return std::nullopt;
    }
    const double x = m_value->get<double>();
    if (!std::isfinite(x) || x < lo || x > hi) {
        problem("expected " + range + ", got " + describe(*m_value));
        return std::nullopt;
    }
    return x;
}

std::optional<double> JsonValue::field(const FieldRange& range, bool required) const {
    const JsonValue member = (*this)[range.name];
    if (member.missing(required))
        return std::nullopt;
    const bool number = range.whole ? member.m_value->is_number_integer() : member.m_value->is_number();
    const double x = member.m_value->is_number() ? member.m_value->get<double>() : 0.0;
    if (!number || !range.contains(x)) {
        member.problem("expected " + range.describe() + ", got " + describe(*member.m_value));
        return std::nullopt;
    }
    return x;
}

std::optional<int> JsonValue::integer(int lo, int hi, bool required) const {
    if (missing(required))
        return std::nullopt;
    if (!m_value->is_number_integer() || m_value->get<long long>() < lo || m_value->get<long long>() > hi) {
        problem("expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + describe(*m_value));
        return std::nullopt;
    }
    return int(m_value->get<long long>());
}

std::optional<std::string> JsonValue::string(bool required) const {
    if (missing(required))
        return std::nullopt;
    if (!m_value->is_string()) {
        problem("expected a string, got " + describe(*m_value));
        return std::nullopt;
    }
    return m_value->get<std::string>();
}

std::optional<bool> JsonValue::boolean(bool required) const {
    if (missing(required))
        return std::nullopt;
    if (!m_value->is_boolean()) {
        problem("expected true or false, got " + describe(*m_value));
        return std::nullopt;
    }
    return m_value->get<bool>();
}

std::optional<Vec3> JsonValue::vec3(bool required) const {
    if (missing(required))
        return std::nullopt;
    if (!m_value->is_array() || m_value->size() != 3) {
        problem("expected an array of 3 numbers, got " + describe(*m_value));
        return std::nullopt;
    }
    Vec3 v;
    for (int i = 0; i < 3; ++i) {
        const auto& x = (*m_value)[std::size_t(i)];
        if (!x.is_number() || !std::isfinite(x.get<double>())) {
            problem("expected an array of 3 finite numbers, got " + describe(*m_value));
            return std::nullopt;
        }
        v[i] = x.get<double>();
    }
    return v;
}

std::optional<std::array<int, 3>> JsonValue::int3(int lo, int hi, bool required) const {
    if (missing(required))
        return std::nullopt;
    if (!m_value->is_array() || m_value->size() != 3) {
        problem("expected an array of 3 integers, got " + describe(*m_value));
        return std::nullopt;
    }
    std::array<int, 3> out{};
    for (std::size_t i = 0; i < 3; ++i) {
        const auto& x = (*m_value)[i];
        if (!x.is_number_integer() || x.get<long long>() < lo || x.get<long long>() > hi) {
            problem("expected 3 integers in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + describe(*m_value));
            return std::nullopt;
        }
        out[i] = int(x.get<long long>());
    }
    return out;
}

}  // namespace softtouch::io
