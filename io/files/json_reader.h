#pragma once
/// Reading JSON with errors a person can act on: every problem names the file, the JSON pointer of
/// the value and what was expected ("scene.softtouch: /objects/0/material/mass: expected a number
/// in [1e-12, 1e12] (kg), got -1"). Problems are collected, not thrown, so `validate` lists them all.

#include "core/base/ranges.h"
#include "core/base/types.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace softtouch::io {

/// The problems found in one file.
class JsonIssues {
public:
    explicit JsonIssues(std::string file) : m_file(std::move(file)) {}
    /// Records a problem at a JSON pointer ("" for the whole document).
    void add(const std::string& pointer, const std::string& problem);
    /// Records a problem that has no place in the document (a missing referenced file, …).
    void addGeneral(const std::string& problem);
    bool empty() const { return m_messages.empty(); }
    const std::vector<std::string>& messages() const { return m_messages; }
    /// The first problem, plus how many more there are.
    std::string summary() const;
    const std::string& file() const { return m_file; }

private:
    static constexpr std::size_t kMaxListed = 1000;  ///< Problems listed one by one; the rest are counted.
    std::string m_file;
    std::vector<std::string> m_messages;
    std::size_t m_unlisted = 0;
};

/// Parses a file into JSON; on failure records the line and column of the syntax error.
std::optional<nlohmann::json> parseJsonFile(const std::string& path, JsonIssues& issues);
/// The same for text already read (a GLB's JSON chunk): nesting depth, duplicate keys and syntax checked alike.
std::optional<nlohmann::json> parseJsonText(std::string_view text, JsonIssues& issues);

/// One JSON value (possibly absent) with its pointer; typed reads report into JsonIssues.
class JsonValue {
public:
    JsonValue(const nlohmann::json* value, std::string pointer, JsonIssues* issues)
        : m_value(value), m_pointer(std::move(pointer)), m_issues(issues) {}

    bool exists() const { return m_value != nullptr; }
    bool isArray() const { return m_value && m_value->is_array(); }
    bool isObject() const { return m_value && m_value->is_object(); }
    bool isNumber() const { return m_value && m_value->is_number(); }
    std::size_t size() const { return isArray() ? m_value->size() : 0; }
    const std::string& pointer() const { return m_pointer; }
    /// Member `key` (absent when this is not an object or has no such key).
    JsonValue operator[](const char* key) const;
    /// Element i of an array.
    JsonValue at(std::size_t i) const;

    /// Reports a problem at this value.
    void problem(const std::string& what) const;
    /// Reports members not in `allowed` (catches typos such as "stifness").
    void checkKeys(std::initializer_list<const char*> allowed) const;
    /// Requires an object; reports otherwise. Absent is fine unless required.
    bool expectObject(bool required = false) const;

    std::optional<double> number(double lo, double hi, const char* unit = "", bool required = false) const;
    std::optional<int> integer(int lo, int hi, bool required = false) const;
    /// The member `range.name` of this object, checked against `range` (core/base/ranges.h): a whole number must be
    /// written as an integer. Problems are reported at the member.
    std::optional<double> field(const FieldRange& range, bool required = false) const;
    std::optional<std::string> string(bool required = false) const;
    std::optional<bool> boolean(bool required = false) const;
    /// Three finite numbers.
    std::optional<Vec3> vec3(bool required = false) const;
    /// Three integers in [lo, hi].
    std::optional<std::array<int, 3>> int3(int lo, int hi, bool required = false) const;

private:
    bool missing(bool required) const;
    const nlohmann::json* m_value;
    std::string m_pointer;
    JsonIssues* m_issues;
};

}  // namespace softtouch::io
