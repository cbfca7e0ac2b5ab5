#include "model/GroomReport.h"

namespace hair
{

const char* toString(RestOutcome outcome)
{
  switch (outcome)
  {
  case RestOutcome::AsGrown:
    return "as grown";
  case RestOutcome::Held:
    return "held";
  case RestOutcome::Unstable:
    return "unstable";
  case RestOutcome::BeyondBending:
    return "beyond the elastic range";
  }
  return "unknown";
}

const std::vector<GroomReportValue>& groomReportValues()
{
  static const std::vector<GroomReportValue> table = {
      {"FitError", "fit_error", "m", [](const GroomReport& r) { return r.fitError; }},
      {"RestShapeStatus", "rest_status", "1",
       [](const GroomReport& r) { return double(static_cast<int>(r.outcome)); }},
      {"GroomDeviation", "groom_deviation", "m", [](const GroomReport& r) { return r.deviation; }},
      {"Stability", "stability", "1", [](const GroomReport& r) { return r.stability; }},
  };
  return table;
}

} // namespace hair
