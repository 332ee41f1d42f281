// CSV fields as RFC 4180 writes them (joint and body names may hold commas or quotes).

#include <gtest/gtest.h>

#include "idto/core/csv.hpp"

namespace idto {
namespace {

TEST(Csv, FieldsAreQuotedOnlyWhenNeeded) {
  EXPECT_EQ(CsvField("q:elbow"), "q:elbow");
  EXPECT_EQ(CsvField(""), "");
  EXPECT_EQ(CsvField("q:a,b"), "\"q:a,b\"");
  EXPECT_EQ(CsvField("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(CsvField("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(CsvField("cr\r"), "\"cr\r\"");
}

}  // namespace
}  // namespace idto
