// SPDX-License-Identifier: Apache-2.0
#pragma once
// The CSV half of the survey reader (io/survey_reader.h documents the format). Internal to io/.

#include <initializer_list>
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

// One quantity a survey table carries in a column of its own, as its header may name it.
struct HeaderRole {
  const char* name;                  // in messages: "point id", "easting"
  std::vector<std::string> aliases;  // header names as SurveyHeaderName gives them
};

// The role a header field names (its index in `roles`), or -1.
int HeaderRoleOf(const std::string& field, const std::vector<HeaderRole>& roles);

// The column of each role in a header row (-1: none; extra columns are left alone). Throws
// InputError "name:line: column A and column B both name the ROLE; expected one column for it".
std::vector<int> MatchHeaderRoles(const std::vector<std::string>& fields,
                                  const std::vector<HeaderRole>& roles, const std::string& name,
                                  int line);

// The names of the `required` roles without a column, ", "-separated; empty when all have one.
std::string MissingRoles(const std::vector<int>& columns, const std::vector<HeaderRole>& roles,
                         std::initializer_list<int> required);

// "column 3" for the 0-based index 2.
std::string SurveyColumn(int index);

// The number of a field in `column` holding `role` (a decimal comma read as a point when
// `decimal_comma`). Throws InputError "name:line: column N (ROLE) is empty; expected EXPECTED"
// or "... is not a finite number (K characters); expected EXPECTED".
double SurveyNumber(std::string text, int column, const char* role, bool decimal_comma,
                    const std::string& name, int line, const std::string& expected);

// The point id in `column`: not empty and without control characters, else InputError.
std::string SurveyPointId(const std::vector<std::string>& fields, int column,
                          const std::string& name, int line);

// Throws InputError "name:line: the <what> has a control character; ..." when `text` has one.
void CheckPrintableField(const std::string& text, const std::string& what,
                         const std::string& name, int line);

// "12,345" as "12.345": a field of a ';'- or tab-separated export with one decimal comma and no
// point; any other text unchanged.
std::string WithDecimalPoint(std::string text);

}  // namespace wallcal::io
