// SPDX-License-Identifier: Apache-2.0
#pragma once
// The CSV half of the survey reader (io/survey_reader.h documents the format). Internal to io/.

#include <string>
#include <string_view>
#include <vector>

#include "io/types.h"

namespace wallcal::io {

// Every point row of a survey CSV, in file order. Throws InputError as ReadSurvey documents.
std::vector<SurveyPoint> ParseSurveyCsv(std::string_view text, const std::string& name,
                                        SurveyColumns columns);

// Splits one CSV row at commas; a field may be quoted ("a, b", with "" for a quote inside).
// Blanks around fields (outside quotes) are dropped. False on a quote that is never closed.
bool SplitCsvRow(std::string_view row, std::vector<std::string>* fields);

}  // namespace wallcal::io
