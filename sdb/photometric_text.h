// Text helpers the photometric file readers share (sdb/ies.h, sdb/eulumdat.h): trimming a line, quoting an
// excerpt of it in a message, and writing a number as the messages show it.
#pragma once

#include <string>
#include <string_view>

namespace fly::sdb {

// `s` without leading and trailing blanks (space, tab, CR, form feed, vertical tab).
std::string_view trimBlanks(std::string_view s);
// 's', printable and shortened as messages quote file contents (base/error.h, printableExcerpt).
std::string quotedExcerpt(std::string_view s);
// Whole numbers in full (a count of 2000000000, not 2e+09), others with 6 significant digits.
std::string formatNumber(double v);

}  // namespace fly::sdb
