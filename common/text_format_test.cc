#include "common/text_format.h"

#include <gtest/gtest.h>

#include <string>

namespace aslam {
namespace {

TEST(Format, FormatsLikePrintf) {
  EXPECT_EQ(Format("goal (%.2f, %.2f) #%d %s", 1.0, -2.345, 7, "ok"), "goal (1.00, -2.35) #7 ok");
  EXPECT_EQ(Format("%.17g", 0.1), "0.10000000000000001");
}

TEST(Format, KeepsTextLongerThanAnyFixedBuffer) {
  const std::string long_text(1000, 'x');
  EXPECT_EQ(Format("[%s]", long_text.c_str()), "[" + long_text + "]");
  EXPECT_EQ(Format("%s", ""), "");
}

TEST(CsvField, QuotesOnlyWhatNeedsIt) {
  EXPECT_EQ(CsvField("plain text"), "plain text");
  EXPECT_EQ(CsvField("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("two\nlines"), "\"two\nlines\"");
}

}  // namespace
}  // namespace aslam
