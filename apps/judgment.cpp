#include "judgment.h"

#include <iostream>

namespace imuconv::cli {

int Judge(bool as_json, const std::function<Judgment()>& work) {
  Judgment judgment;
  try {
    judgment = work();
  } catch (const std::exception& e) {
    // Nothing could be judged: neither consistent (0) nor inconsistent (1).
    return ReportFailure(e);
  }
  if (judgment.printed_elsewhere) return judgment.exit_code;
  if (as_json)
    std::cout << WithWarnings(judgment.json(), judgment.warnings).dump(1) << "\n";
  else
    judgment.print_table(std::cout);
  return judgment.exit_code;
}

}  // namespace imuconv::cli
