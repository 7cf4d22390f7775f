#include "report_destination.h"

#include <iostream>

#include "imuconv/printable.h"

namespace imuconv::cli {

CLI::Option* AddReportOption(CLI::App& sub, std::string& path, const std::string& contents) {
  return AddOutputPathOption(sub, "--report", path,
                             "Also write a self-contained HTML report: " + contents, "OUT.html");
}

ReportDestination::ReportDestination(const std::string& path) {
  if (!path.empty()) out_.emplace(path);
}

void ReportDestination::RefuseIfSame(const std::string& input, const std::string& role) const {
  if (out_ && !input.empty()) out_->RefuseIfSame(input, role);
}

void ReportDestination::RefuseIfLoadedObject() const {
  if (out_) out_->RefuseIfLoadedObject();
}

void ReportDestination::RefuseIfSameOutput(const pipeline::OutputFile& other,
                                           const std::string& other_role) const {
  if (out_) out_->RefuseIfSameOutput(other, other_role);
}

void ReportDestination::Write(const std::function<report::HtmlDocument()>& page,
                              const CommandContext& ctx, bool announce) {
  if (!out_) return;
  out_->RefuseIfLoadedObject();
  out_->Write(page());
  written_ = true;
  if (announce) Announce(ctx);
}

void ReportDestination::Announce(const CommandContext& ctx) const {
  if (written_ && !ctx.quiet()) std::cerr << "wrote " << Printable(out_->path()) << "\n";
}

std::vector<std::pair<std::string, std::string>> GivenInputs(
    std::initializer_list<std::pair<const char*, const std::string*>> options) {
  std::vector<std::pair<std::string, std::string>> inputs;
  for (const auto& [role, path] : options)
    if (!path->empty()) inputs.emplace_back(role, *path);
  return inputs;
}

}  // namespace imuconv::cli
