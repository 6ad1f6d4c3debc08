#pragma once
// A small JSON Schema (draft-07) checker for the keywords our export schemas use — type, enum, const,
// required, properties, additionalProperties, minProperties, maxProperties, items, minItems, maxItems,
// minimum, maximum, exclusiveMinimum, $ref to "#/definitions/NAME" — written here because Debian has no
// JSON Schema library for C++. An unknown keyword is an error (so a schema cannot silently ask for more
// than is checked). Returns one line per violation, with the JSON pointer of the value.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace hmp::test {

class JsonSchema {
 public:
  explicit JsonSchema(nlohmann::json schema) : root_(std::move(schema)) {}

  std::vector<std::string> validate(const nlohmann::json& doc) const {
    std::vector<std::string> errors;
    check(root_, doc, "", errors);
    return errors;
  }

 private:
  static bool has_type(const nlohmann::json& v, const std::string& t) {
    if (t == "object") return v.is_object();
    if (t == "array") return v.is_array();
    if (t == "string") return v.is_string();
    if (t == "number") return v.is_number();
    if (t == "integer")
      return v.is_number_integer() ||
             (v.is_number_float() && v.get<double>() == static_cast<double>(static_cast<long long>(v.get<double>())));
    if (t == "boolean") return v.is_boolean();
    if (t == "null") return v.is_null();
    return false;
  }

  const nlohmann::json& resolve(const nlohmann::json& s) const {
    if (!s.contains("$ref")) return s;
    const std::string ref = s["$ref"];
    const std::string prefix = "#/definitions/";
    return root_.at("definitions").at(ref.substr(prefix.size()));
  }

  void check(const nlohmann::json& schema_in, const nlohmann::json& v, const std::string& at,
             std::vector<std::string>& errors) const {
    const nlohmann::json& s = resolve(schema_in);
    auto fail = [&](const std::string& what) { errors.push_back((at.empty() ? "/" : at) + ": " + what); };
    for (const auto& [key, rule] : s.items()) {
      if (key == "type") {
        bool ok = false;
        if (rule.is_string())
          ok = has_type(v, rule);
        else
          for (const auto& t : rule) ok = ok || has_type(v, t);
        if (!ok) return fail("not of type " + rule.dump());
      } else if (key == "enum") {
        if (std::find(rule.begin(), rule.end(), v) == rule.end()) fail(v.dump() + " not one of " + rule.dump());
      } else if (key == "const") {
        if (v != rule) fail(v.dump() + " is not " + rule.dump());
      } else if (key == "required") {
        for (const auto& name : rule)
          if (v.is_object() && !v.contains(name)) fail("missing \"" + name.get<std::string>() + "\"");
      } else if (key == "properties") {
        if (!v.is_object()) continue;
        for (const auto& [name, sub] : rule.items())
          if (v.contains(name)) check(sub, v[name], at + "/" + name, errors);
      } else if (key == "additionalProperties") {
        if (!v.is_object()) continue;
        for (const auto& [name, value] : v.items()) {
          if (s.contains("properties") && s["properties"].contains(name)) continue;
          if (rule.is_boolean()) {
            if (!rule.get<bool>()) fail("unexpected key \"" + name + "\"");
          } else {
            check(rule, value, at + "/" + name, errors);
          }
        }
      } else if (key == "minProperties") {
        if (v.is_object() && v.size() < rule.get<std::size_t>()) fail("fewer than " + rule.dump() + " keys");
      } else if (key == "maxProperties") {
        if (v.is_object() && v.size() > rule.get<std::size_t>()) fail("more than " + rule.dump() + " keys");
      } else if (key == "items") {
        if (v.is_array())
          for (std::size_t i = 0; i < v.size(); ++i) check(rule, v[i], at + "/" + std::to_string(i), errors);
      } else if (key == "minItems") {
        if (v.is_array() && v.size() < rule.get<std::size_t>()) fail("fewer than " + rule.dump() + " items");
      } else if (key == "maxItems") {
        if (v.is_array() && v.size() > rule.get<std::size_t>()) fail("more than " + rule.dump() + " items");
      } else if (key == "minimum") {
        if (v.is_number() && v.get<double>() < rule.get<double>()) fail(v.dump() + " < " + rule.dump());
      } else if (key == "maximum") {
        if (v.is_number() && v.get<double>() > rule.get<double>()) fail(v.dump() + " > " + rule.dump());
      } else if (key == "exclusiveMinimum") {
        if (v.is_number() && v.get<double>() <= rule.get<double>()) fail(v.dump() + " ≤ " + rule.dump());
      } else if (key == "$schema" || key == "$comment" || key == "title" || key == "description" ||
                 key == "definitions" || key == "$ref") {
        continue;
      } else {
        fail("schema keyword \"" + key + "\" is not checked by this validator");
      }
    }
  }

  nlohmann::json root_;
};

}  // namespace hmp::test
