#include "imuconv/report/report_output.h"

#include "imuconv/pipeline/output_file.h"
#include "imuconv/printable.h"
#include "imuconv/registry.h"
#include "imuconv/report/html_document.h"

namespace imuconv::report {
namespace {

// OutputFile's messages start with the path; the option is what the user needs to see too.
template <typename F>
void Prefixed(F f) {
  try {
    f();
  } catch (const Error& e) {
    throw Error(std::string("--report: ") + e.what());
  }
}

}  // namespace

ReportOutput::ReportOutput(const std::string& path) {
  Prefixed([&] { file_ = std::make_unique<pipeline::OutputFile>(path); });
  if (file_->is_stdout())
    throw Error("--report: " + Printable(path) +
                ": standard output holds the command's summary; name a file for the report");
}

ReportOutput::~ReportOutput() = default;

void ReportOutput::RefuseIfSame(const std::string& input, const std::string& role) const {
  Prefixed([&] { file_->refuse_if_same(input, role); });
}

void ReportOutput::RefuseIfLoadedObject() const {
  Prefixed([&] { file_->refuse_if_loaded_object(); });
}

void ReportOutput::RefuseIfSameOutput(const pipeline::OutputFile& other,
                                      const std::string& other_role) const {
  // Not Prefixed: the message names both options itself.
  file_->refuse_if_same_output("--report", other, other_role);
}

void ReportOutput::Write(const HtmlDocument& doc) {
  Prefixed([&] {
    file_->write(doc.Render());
    file_->commit();
  });
}

const std::string& ReportOutput::path() const { return file_->path(); }

}  // namespace imuconv::report
