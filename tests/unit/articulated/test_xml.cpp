#include <gtest/gtest.h>

#include "pliant/core/error.h"
#include "xml.h"

namespace pliant::articulated {
namespace {

TEST(Xml, ParsesElementsAttributesAndSkipsComments) {
  const XmlElement e = parse_xml(
      "<?xml version=\"1.0\"?>\n<!-- c -->\n<a x='1' y=\"&lt;2&gt;\">text<b/><!-- <c/> --><c z=\"3\"></c></a>\n", "t.xml");
  EXPECT_EQ(e.name, "a");
  EXPECT_EQ(*e.attr("y"), "<2>");
  ASSERT_EQ(e.children.size(), 2u);
  EXPECT_EQ(e.children[1].name, "c");
  EXPECT_EQ(e.children[1].line, 3);
}

TEST(Xml, ReportsErrorsWithLines) {
  EXPECT_THROW(parse_xml("<a>\n<b>\n</a>", "t.xml"), InputError);
  EXPECT_THROW(parse_xml("<a x=1/>", "t.xml"), InputError);
  EXPECT_THROW(parse_xml("<a/><b/>", "t.xml"), InputError);
  try {
    parse_xml("<a>\n\n<b x=\"1\" x=\"2\"/></a>", "t.xml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pliant::articulated
