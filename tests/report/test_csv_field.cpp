#include "report/csv_field.h"

#include <gtest/gtest.h>

#include "tests/support/csv_line.h"

using nns::report::csv_field;
using nns::testing::csv_fields;

// A plain label stays as it was (the files of every earlier evaluation read the same); one
// with a comma, a quote or a line break is quoted, and reads back as itself.
TEST(CsvField, PlainFieldsStayAndOthersReadBackAsThemselves) {
  EXPECT_EQ(csv_field("lh-s1/G @64 guided"), "lh-s1/G @64 guided");
  EXPECT_EQ(csv_field(""), "");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  for (std::string s : {"runs/a,b/G", "x\"y", "two\nlines", "\",\"", "end,"}) {
    const auto f = csv_fields(csv_field(s) + ",1");
    ASSERT_EQ(f.size(), 2u) << s;
    EXPECT_EQ(f[0], s);
    EXPECT_EQ(f[1], "1");
  }
}
