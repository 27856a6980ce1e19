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

// Splits one CSV row at `delimiter` (',', ';' or a tab); a field may be quoted ("a, b", with ""
// for a quote inside). Blanks around fields (outside quotes) are dropped. False on a quote that
// is never closed.
bool SplitCsvRow(std::string_view row, std::vector<std::string>* fields, char delimiter = ',');

// True when `fields` (a first row, split) name every column a survey CSV needs, as the reader
// accepts them (docs/survey-files.md).
bool IsSurveyCsvHeader(const std::vector<std::string>& fields);

// The field delimiter of a survey CSV, from its first row: ';' when the row has one (European
// exports, with decimal commas), a tab when it has at least as many tabs as commas, else ','.
// Quoted text is not counted.
char SurveyCsvDelimiter(std::string_view line);

// A header field as the readers compare it: a bracketed unit dropped ("Northing (m)",
// "Elev [m]"), lower-cased, without blanks, '_', '-' and '.' ("Point ID" -> "pointid").
std::string SurveyHeaderName(const std::string& field);

// Throws InputError "name:line: the <what> has a control character; ..." when `text` has one.
void CheckPrintableField(const std::string& text, const std::string& what,
                         const std::string& name, int line);

// "12,345" as "12.345": a field of a ';'- or tab-separated export with one decimal comma and no
// point; any other text unchanged.
std::string WithDecimalPoint(std::string text);

}  // namespace wallcal::io
