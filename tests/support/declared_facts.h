// Facts about a built-in plugin that a test states from the plugin's documentation (a
// convention's block order, a scheme's noise cells), declared in that system's own test file
// rather than in a shared table (issue 25: adding a system touches no file outside its plugin,
// its kernel and its tests). A declaration registers itself at static initialization; the
// shared test of the fact then checks, for every declaration, that the loaded plugin says the
// same, and, for every plugin of the kind the registry loads from the built-in plugin
// directory, that some test file declares it, so a new system without its line still fails,
// naming the line to add and where.
#pragma once

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

#include "imuconv/plugin_kind.h"
#include "imuconv/registry.h"

namespace imuconv::test {

/// The KIND argument of a declaration macro for a scheme's plugin kind.
inline const char* SchemeKindName(PluginKind kind) {
  return kind == PluginKind::Propagator ? "Propagator" : "Preintegrator";
}

/// Where a declaration was written, for the messages that name it.
struct DeclarationSite {
  const char* file;
  int line;
};
inline std::string Describe(const DeclarationSite& site) {
  return std::string(site.file) + ":" + std::to_string(site.line);
}

/// The declarations of one kind of fact (Tag::Facts, the value declared), by plugin id, as
/// every test file of the executable declared them.
template <typename Tag>
class DeclaredFacts {
 public:
  using Facts = typename Tag::Facts;
  struct Entry {
    Facts facts;
    DeclarationSite site;
  };
  /// Registers `facts` for `id` (called once per declaration, at static initialization). A
  /// second declaration of one id is kept aside and reported by CheckNoDuplicates.
  static bool Add(const std::string& id, Facts facts, DeclarationSite site) {
    auto [it, inserted] = Table().emplace(id, Entry{facts, site});
    if (!inserted)
      Duplicates().push_back(id + " at " + Describe(site) + " and " + Describe(it->second.site));
    return inserted;
  }
  static const std::map<std::string, Entry>& All() { return Table(); }
  static void CheckNoDuplicates() {
    for (const std::string& d : Duplicates())
      ADD_FAILURE() << Tag::kWhat << " declared twice: " << d;
  }
  /// The shared test of the fact: no id declared twice; for each declaration, the plugin `id`
  /// of `kind` is loaded in `registry` (else the check stops there) and `check_one(id, facts)`,
  /// which states the fact's own expectations, holds; and every plugin of `kind` the registry
  /// loaded has a declaration (`where` and `line` as CheckEveryLoadedIdDeclared takes them).
  template <typename CheckOne>
  static void CheckAll(const Registry& registry, PluginKind kind, const char* where,
                       const std::string& line, CheckOne check_one) {
    CheckNoDuplicates();
    for (const auto& [id, entry] : All()) {
      SCOPED_TRACE("declared at " + Describe(entry.site));
      ASSERT_TRUE(registry.has(kind, id)) << id << " is declared but not loaded";
      check_one(id, entry.facts);
    }
    CheckEveryLoadedIdDeclared(registry.ids(kind), where, line.c_str());
  }

  /// Every id in `loaded` (the registry's plugins of the kind) has a declaration; `where` says
  /// in which file a system's declaration belongs and `line` how it reads, "<id>" in either
  /// standing for the plugin's id.
  static void CheckEveryLoadedIdDeclared(const std::vector<std::string>& loaded, const char* where,
                                         const char* line) {
    for (const std::string& id : loaded)
      EXPECT_TRUE(Table().count(id))
          << "'" << id
          << "' is loaded from the built-in plugin directory, but no test declares its "
          << Tag::kWhat << ": add " << WithId(line, id) << " to " << WithId(where, id);
  }

 private:
  static std::string WithId(std::string text, const std::string& id) {
    for (std::size_t at = text.find("<id>"); at != std::string::npos;
         at = text.find("<id>", at + id.size()))
      text.replace(at, 4, id);
    return text;
  }
  static std::map<std::string, Entry>& Table() {
    static std::map<std::string, Entry> table;
    return table;
  }
  static std::vector<std::string>& Duplicates() {
    static std::vector<std::string> duplicates;
    return duplicates;
  }
};

}  // namespace imuconv::test
