// Tests for lib/io/inp_deck.* (SPEC 7): the traps of real decks, and every error naming its file and line.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/quote_text.hpp"
#include "error_message.hpp"
#include "io/inp_deck.hpp"
#include "mesh/contact_model.hpp"
#include "test_support.hpp"

namespace contactnn::io {
namespace {

namespace fs = std::filesystem;
using mesh::Vec3;

fs::path dir() { return testing::test_output_dir("inp_deck"); }

fs::path write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// Two unit cubes stacked along z (ids 1-8 lower, 11-18 upper, with a gap of 0.1), as node lines.
const std::string kNodes =
    "*NODE, NSET=NALL\n"
    "1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, 1\n"
    "11, 0, 0, 1.1\n12, 1, 0, 1.1\n13, 1, 1, 1.1\n14, 0, 1, 1.1\n15, 0, 0, 2.1\n16, 1, 0, 2.1\n17, 1, 1, "
    "2.1\n"
    "18, 0, 1, 2.1\n";
const std::string kElements =
    "*ELEMENT, TYPE=C3D8, ELSET=LOWER\n1, 1, 2, 3, 4, 5, 6, 7, 8\n"
    "*ELEMENT, TYPE=C3D8R, ELSET=UPPER\n2, 11, 12, 13, 14, 15, 16, 17, 18\n";
// The lower cube's top is S2 (5-8-7-6), the upper cube's bottom S1 (1-2-3-4).
const std::string kSurfaces = "*SURFACE, NAME=STOP\nLOWER, S2\n*SURFACE, NAME=SBOTTOM, TYPE=ELEMENT\n2, S1\n";

mesh::ContactModel read_text(const std::string& name, const std::string& text) {
  return read_inp_deck(write(dir() / name, text));
}

/// The message of the FormatError (or IoError) that reading `text` throws; "" if it throws nothing.
template <class Exception>
std::string error_of(const std::string& name, const std::string& text) {
  try {
    (void)read_text(name, text);
  } catch (const Exception& e) {
    return e.what();
  }
  return "";
}

std::string location(const std::string& name, int line) {
  return "'" + (dir() / name).string() + "':" + std::to_string(line) + ":";
}

TEST(InpDeck, ReadsNodesElementsSurfacesAndPairs) {
  const auto model = read_text(
      "basic.inp", "** a comment\n*HEADING\nanything, at all\n" + kNodes + kElements + kSurfaces +
                       "*CONTACT PAIR, INTERACTION=I\nSBOTTOM, STOP\n*STEP\n*STATIC\n1., 1.\n*END STEP\n");
  EXPECT_EQ(model.mesh.node_count(), 16);
  EXPECT_EQ(model.mesh.element_count(), 2);
  ASSERT_EQ(model.pairs.size(), 1u);
  const mesh::SurfaceMesh master = mesh::master_surface(model, 0);
  ASSERT_EQ(master.segments.size(), 1u);
  EXPECT_EQ(master.node_ids, (std::vector<long>{5, 6, 7, 8}));
  // Outward from the lower cube: +z. A = node 5 (S2's first corner), then counter-clockwise from above.
  const auto& q = master.segments[0];
  EXPECT_EQ(master.node_ids[static_cast<std::size_t>(q[0])], 5);
  EXPECT_EQ(master.node_ids[static_cast<std::size_t>(q[1])], 6);
  EXPECT_EQ(master.node_ids[static_cast<std::size_t>(q[2])], 7);
  EXPECT_EQ(master.node_ids[static_cast<std::size_t>(q[3])], 8);
  const mesh::SlaveNodes slaves = mesh::slave_nodes(model, 0, master);
  std::vector<long> ids;
  for (int n : slaves.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{11, 12, 13, 14}));
}

TEST(InpDeck, LexicalTrapsCaseCrlfTabsTrailingCommasBlankFieldsBomAndDExponents) {
  const std::string text =
      "\xEF\xBB\xBF** BOM, CRLF, tabs, trailing commas, lower case, blank coordinate, D exponent\r\n"
      "*node,\tnset=nall\r\n1,\t0.,\t0.,\t0.,\r\n2, 1.0D+00, 0, 0\r\n3, 1, 1, \r\n4, 0, 1, 0\r\n5, 0, 0, "
      "1\r\n"
      "6, 1, 0, 1\r\n7, +1, 1, 1\r\n8, 0, 1, 1E0\r\n"
      "*Element, Type=c3d8i, Elset=Body\r\n1,\t1, 2, 3, 4, 5, 6, 7, 8,\r\n"
      "*Surface, name=Top\r\nbody, s2,\r\n*surface, type=NODE, name=pts\r\n  1,\r\n2\r\n"
      "*contact pair , type=node to surface\r\nPTS, top\r\n";
  const auto model = read_text("lexical.inp", text);
  EXPECT_EQ(model.mesh.position(model.mesh.find_node(3)), Vec3(1, 1, 0));  // blank z is 0
  EXPECT_EQ(model.mesh.position(model.mesh.find_node(2)), Vec3(1, 0, 0));
  EXPECT_EQ(model.mesh.position(model.mesh.find_node(7)), Vec3(1, 1, 1));
  const auto master = mesh::master_surface(model, 0);
  EXPECT_EQ(master.segments.size(), 1u);
  const auto slaves = mesh::slave_nodes(model, 0, master);
  ASSERT_EQ(slaves.nodes.size(), 2u);
  EXPECT_EQ(model.mesh.node_id(slaves.nodes[0]), 1);
  EXPECT_EQ(model.mesh.node_id(slaves.nodes[1]), 2);
}

TEST(InpDeck, Calculix20NodeElementsSpanTwoLinesAndUseTheirCorners) {
  // Corners 1-8 a unit cube; the mid-side nodes 9-20 anywhere (never segment corners).
  std::string text =
      "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n8, 0, 1, "
      "1\n";
  for (int i = 9; i <= 20; ++i) text += std::to_string(i) + ", 0.5, 0.5, " + std::to_string(0.01 * i) + "\n";
  text +=
      "*ELEMENT, TYPE=C3D20R\n"
      "     1,     1,     2,     3,     4,     5,     6,     7,     8,     9,    10,\n"
      "          11,    12,    13,    14,    15,    16,    17,    18,    19,    20\n"
      "*SURFACE, NAME=S\n1, S2\n*SURFACE, NAME=N, TYPE=NODE\n9\n*CONTACT PAIR\nN, S\n";
  const auto model = read_text("c3d20.inp", text);
  ASSERT_EQ(model.mesh.element_count(), 1);
  EXPECT_EQ(model.mesh.element_nodes(0).size(), 20u);
  const auto master = mesh::master_surface(model, 0);
  // The face's corners are its segment; its mid-side nodes (edges 5-6, 6-7, 7-8, 8-5: nodes 13-16) are nodes
  // of the surface too, for the surface search's 8-node face (SPEC 9).
  ASSERT_EQ(master.segments.size(), 1u);
  std::vector<long> corners;
  for (int n : master.segments[0]) corners.push_back(master.node_ids[static_cast<std::size_t>(n)]);
  std::sort(corners.begin(), corners.end());
  EXPECT_EQ(corners, (std::vector<long>{5, 6, 7, 8}));
  EXPECT_EQ(master.node_ids, (std::vector<long>{5, 6, 7, 8, 13, 14, 15, 16}));
}

TEST(InpDeck, GenerateAndSetsNamedInsideSets) {
  const std::string text =
      kNodes + kElements +
      "*NSET, NSET=A, GENERATE\n11, 13\n*NSET, NSET=B\n14,\n*NSET, NSET=AB\na, B,\n"
      "*NSET, NSET=EVERY_OTHER, GENERATE\n1, 7, 2\n"
      "*ELSET, ELSET=E1, GENERATE\n1, 1, 1\n*ELSET, ELSET=ALL\nE1, upper\n"
      "*SURFACE, NAME=M\nALL, S2\n*SURFACE, NAME=SL, TYPE=NODE\nAB\n*CONTACT PAIR\nSL, M\n"
      "*SURFACE, NAME=ODD, TYPE=NODE\nEVERY_OTHER\n*CONTACT PAIR\nODD, M\n";
  const auto model = read_text("sets.inp", text);
  const auto master = mesh::master_surface(model, 0);
  EXPECT_EQ(master.segments.size(), 2u);  // S2 of both cubes
  const auto slaves = mesh::slave_nodes(model, 0, master);
  std::vector<long> ids;
  for (int n : slaves.nodes) ids.push_back(model.mesh.node_id(n));
  EXPECT_EQ(ids, (std::vector<long>{11, 12, 13, 14}));
  const auto odd = mesh::slave_nodes(model, 1, master);
  ids.clear();
  for (int n : odd.nodes) ids.push_back(model.mesh.node_id(n));
  // 1, 3, 5, 7: 5 and 7 are master nodes (the lower cube's top) and are left out.
  EXPECT_EQ(ids, (std::vector<long>{1, 3}));
  EXPECT_EQ(odd.shared_with_master, 2);
}

TEST(InpDeck, NodeAndElementSurfacesOfOneNameAreKeptApartAndTheRoleIsThePosition) {
  // The names say the opposite of the roles (as in hueeber1.inp): the first field is the slave.
  const std::string text = kNodes + kElements +
                           "*SURFACE, NAME=MASTER, TYPE=NODE\n11\n12\n"
                           "*SURFACE, NAME=MASTER, TYPE=ELEMENT\nUPPER, S1\n"
                           "*SURFACE, NAME=SLAVE\nLOWER, S2\n"
                           "*CONTACT PAIR, TYPE=NODE TO SURFACE\nMASTER, SLAVE\n"
                           "*CONTACT PAIR, TYPE=SURFACE TO SURFACE\nmaster, slave\n"
                           "*CONTACT PAIR\nMaster, Slave\n";
  const auto model = read_text("same-name.inp", text);
  ASSERT_EQ(model.pairs.size(), 3u);
  const auto master = mesh::master_surface(model, 0);
  EXPECT_EQ(master.node_ids, (std::vector<long>{5, 6, 7, 8}));
  EXPECT_EQ(mesh::slave_nodes(model, 0, master).nodes.size(), 2u);  // the node surface: 11, 12
  EXPECT_EQ(mesh::slave_nodes(model, 1, master).nodes.size(), 4u);  // the element surface's corners
  EXPECT_EQ(mesh::slave_nodes(model, 2, master).nodes.size(), 2u);  // no TYPE: CalculiX's NODE TO SURFACE
  EXPECT_EQ(model.pairs[0].slave_name, "MASTER");
}

TEST(InpDeck, IncludesAreRelativeToTheIncludingFileAndContinueTheBlockBeforeThem) {
  write(dir() / "inc" / "sub" / "more-nodes.inp",
        "11, 0, 0, 1.1\n12, 1, 0, 1.1\n13, 1, 1, 1.1\n14, 0, 1, 1.1\n");
  write(dir() / "inc" / "sub" / "nodes.inp",
        "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 0, 0, 1\n6, 1, 0, 1\n7, 1, 1, 1\n"
        "8, 0, 1, 1\n*INCLUDE, INPUT=more-nodes.inp\n15, 0, 0, 2.1\n");
  const auto model =
      read_inp_deck(write(dir() / "inc" / "main.inp",
                          "*INCLUDE, INPUT=sub/nodes.inp\n16, 1, 0, 2.1\n17, 1, 1, 2.1\n18, 0, 1, 2.1\n" +
                              kElements + kSurfaces + "*CONTACT PAIR\nSBOTTOM, STOP\n"));
  EXPECT_EQ(model.mesh.node_count(), 16);
  EXPECT_EQ(model.mesh.position(model.mesh.find_node(18)), Vec3(0, 1, 2.1));
  EXPECT_EQ(mesh::master_surface(model, 0).segments.size(), 1u);
}

TEST(InpDeck, WedgeAndTetrahedronFacesAreSkippedAndCounted) {
  const std::string text =
      kNodes + kElements +
      "*ELEMENT, TYPE=C3D6, ELSET=W\n3, 1, 2, 3, 5, 6, 7\n*ELEMENT, TYPE=C3D4\n4, 1, 2, 3, 5\n"
      "*SURFACE, NAME=M\nLOWER, S2\nW, S2\nW, S3\n4, S1\n*SURFACE, NAME=SL\nUPPER, S1\n"
      "*CONTACT PAIR\nSL, M\n";
  const auto model = read_text("wedge.inp", text);
  const auto master = mesh::master_surface(model, 0);
  EXPECT_EQ(master.segments.size(), 1u);
  EXPECT_EQ(master.skipped_faces.at("C3D6 triangle"), 1);
  EXPECT_EQ(master.skipped_faces.at("C3D6 quadrilateral"), 1);
  EXPECT_EQ(master.skipped_faces.at("C3D4 triangle"), 1);
}

TEST(InpDeck, RepeatedSetsAndSurfacesAddUp) {
  const std::string text = kNodes + kElements +
                           "*ELSET, ELSET=E\n1\n*ELSET, ELSET=E\n2\n*SURFACE, NAME=M\n1, S2\n"
                           "*SURFACE, NAME=M\n2, S2\n*SURFACE, NAME=SL, TYPE=NODE\n3\n*CONTACT PAIR\nSL, M\n";
  const auto model = read_text("repeat.inp", text);
  EXPECT_EQ(mesh::master_surface(model, 0).segments.size(), 2u);
}

TEST(InpDeck, PairIndexOutOfRangeIsAUsageError) {
  const auto model =
      read_text("pairs.inp", kNodes + kElements + kSurfaces + "*CONTACT PAIR\nSBOTTOM, STOP\n");
  try {
    (void)mesh::contact_pair(model, 1);
    FAIL() << "no exception";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("the deck has 1"), std::string::npos) << e.what();
  }
}

TEST(InpDeck, ANodeSurfaceAsMasterIsRefusedWhenThePairIsUsed) {
  const auto model = read_text("node-master.inp", kNodes + kElements +
                                                      "*SURFACE, NAME=N, TYPE=NODE\n1\n*SURFACE, NAME=M\n"
                                                      "LOWER, S2\n*CONTACT PAIR\nM, N\n");
  try {
    (void)mesh::master_surface(model, 0);
    FAIL() << "no exception";
  } catch (const FormatError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(location("node-master.inp", 27)), std::string::npos) << m;
    EXPECT_NE(m.find("node surface"), std::string::npos) << m;
  }
}

// Each malformed deck: FormatError naming the file, the line and what is wrong.
struct BadDeck {
  const char* name;
  std::string text;
  int line;
  const char* says;
};

TEST(InpDeck, EveryMalformedDeckNamesFileAndLine) {
  const std::string head = kNodes + kElements;  // 21 lines
  const std::vector<BadDeck> cases = {
      {"unknown-elset.inp", head + "*SURFACE, NAME=M\nNOSUCH, S2\n", 23, "unknown element set 'NOSUCH'"},
      {"unknown-nset.inp", head + "*NSET, NSET=A\n1, NOSUCH\n", 23, "field 2: unknown node set 'NOSUCH'"},
      {"unknown-surface.inp", head + kSurfaces + "*CONTACT PAIR\nSBOTTOM, NOSUCH\n", 27,
       "unknown master surface 'NOSUCH'"},
      {"undefined-node.inp", kNodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 99\n", 19,
       "node 99 (node 8 of the element) is not defined"},
      {"bad-number.inp", "*NODE\n1, 0, 0, 0\n2, 1, 0x, 0\n", 3, "field 3: '0x' is not a finite number"},
      {"nan-coordinate.inp", "*NODE\n1, 0, nan, 0\n", 2, "'nan' is not a finite number"},
      {"bad-id.inp", "*NODE\n1a, 0, 0, 0\n", 2, "field 1: '1a' is not a node id"},
      {"bad-face-label.inp", head + "*SURFACE, NAME=M\nLOWER, X2\n", 23, "field 2: 'X2' is not a face label"},
      {"face-out-of-range.inp", head + "*SURFACE, NAME=M\nLOWER, S7\n", 23,
       "faces are S1..S6; the face label says S7"},
      {"missing-face.inp", head + "*SURFACE, NAME=M\nLOWER\n", 23, "needs a face label"},
      {"duplicate-node.inp", "*NODE\n1, 0, 0, 0\n1, 0, 0, 0\n*NODE\n1, 0, 0, 1\n", 5,
       "node 1 is defined again with other coordinates (first at"},
      {"duplicate-element.inp", head + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 18\n", 23,
       "element 1 is defined again differently"},
      {"missing-type.inp", kNodes + "*ELEMENT\n1, 1, 2, 3, 4, 5, 6, 7, 8\n", 18, "missing TYPE="},
      {"missing-name.inp", head + "*SURFACE\nLOWER, S2\n", 22, "missing NAME="},
      {"short-element.inp", kNodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7\n*NSET, NSET=X\n1\n", 19,
       "has 7 node ids before the next keyword, expected 8"},
      {"long-element.inp", kNodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2, 3, 4, 5, 6, 7, 8, 11\n", 19,
       "has 9 node ids, expected 8"},
      // The keyword named as the deck spells it, upper case (not its compared form, "*CONTACTPAIR").
      {"pair-fields.inp", head + kSurfaces + "*Contact   Pair\nSBOTTOM\n", 27,
       "*CONTACT PAIR: expected 'slave surface, master surface'"},
      {"generate-range.inp", "*NSET, NSET=A, GENERATE\n10, 1\n", 2, "GENERATE range 10..1"},
      {"generate-fields.inp", "*NSET, NSET=A, GENERATE\n1\n", 2, "GENERATE needs 'first, last[, increment]'"},
      {"cylindrical-nodes.inp", "*NODE, SYSTEM=C\n1, 1, 0, 0\n", 1, "SYSTEM='C' is not supported"},
      {"cyclic-no-axis.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" + "*CYCLIC SYMMETRY MODEL, N=4, TIE=T\n", 24,
       "no axis line"},
      {"cyclic-bad-n.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" +
           "*CYCLIC SYMMETRY MODEL, N=4x, TIE=T\n0, 0, 0, 1, 0, 0\n",
       24, "N='4x' is not a number of sectors"},
      {"cyclic-unknown-tie.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" +
           "*CYCLIC SYMMETRY MODEL, N=4, TIE=NOSUCH\n0, 0, 0, 1, 0, 0\n",
       24, "TIE='NOSUCH': no *TIE, CYCLIC SYMMETRY of that name"},
      {"cyclic-axis-fields.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" +
           "*CYCLIC SYMMETRY MODEL, N=4, TIE=T\n0, 0, 0, 1, 0\n",
       25, "expected the axis 'ax, ay, az, bx, by, bz', got 5 fields"},
      {"cyclic-axis-point.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" +
           "*CYCLIC SYMMETRY MODEL, N=4, TIE=T\n1, 2, 3, 1, 2, 3\n",
       25, "the axis points a and b coincide"},
      {"cyclic-tie-fields.inp", head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP\n", 23,
       "expected 'dependent surface, independent surface', got 1 fields"},
      {"cyclic-which-tie.inp",
       head + "*TIE, NAME=T, CYCLIC SYMMETRY\nSTOP, SBOTTOM\n" +
           "*TIE, NAME=U, CYCLIC SYMMETRY\nSBOTTOM, STOP\n"
           "*CYCLIC SYMMETRY MODEL, N=4\n0, 0, 0, 1, 0, 0\n",
       26, "TIE= is needed: the deck has 2 *TIE, CYCLIC SYMMETRY cards"},
  };
  for (const BadDeck& c : cases) {
    const std::string message = error_of<FormatError>(c.name, c.text);
    EXPECT_NE(message.find(location(c.name, c.line)), std::string::npos) << c.name << ": " << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << c.name << ": " << message;
  }
}

TEST(InpDeck, IncludeLoopNamesTheChain) {
  write(dir() / "loop" / "b.inp", "*NODE\n2, 1, 0, 0\n*INCLUDE, INPUT=a.inp\n");
  const auto a = write(dir() / "loop" / "a.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=b.inp\n");
  try {
    (void)read_inp_deck(a);
    FAIL() << "no exception";
  } catch (const FormatError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'" + (dir() / "loop" / "b.inp").string() + "':3: *INCLUDE"), std::string::npos) << m;
    EXPECT_NE(m.find("include loop"), std::string::npos) << m;
  }
}

TEST(InpDeck, MissingIncludeIsAnIoErrorNamingTheFile) {
  try {
    (void)read_text("missing-include.inp", "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=not-there.inp\n");
    FAIL() << "no exception";
  } catch (const IoError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(location("missing-include.inp", 3)), std::string::npos) << m;
    EXPECT_NE(m.find("not-there.inp"), std::string::npos) << m;
  }
  EXPECT_THROW((void)read_inp_deck(dir() / "no-such-deck.inp"), IoError);
}

/// The message of the FormatError that reading the deck at `path` throws; "" if it throws nothing.
std::string format_error_of(const fs::path& path) {
  return testing::error_message<FormatError>([&] { (void)read_inp_deck(path); }, "");
}

TEST(InpDeck, ADeckOrIncludeThatIsNotARegularFileIsRefused) {
  // A directory read as an empty file (exit 0, nothing said), /dev/zero read 4 GB into memory, a FIFO waited
  // for a writer: each is refused as what it is, naming the including line.
  fs::create_directories(dir() / "kinds" / "sub");
  const auto include = [&](const std::string& name, const std::string& input) {
    return format_error_of(
        write(dir() / "kinds" / name, "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=" + input + "\n"));
  };
  std::string m = include("directory.inp", "sub");
  EXPECT_NE(m.find("'" + (dir() / "kinds" / "directory.inp").string() + "':3: *INCLUDE"), std::string::npos)
      << m;
  EXPECT_NE(m.find("is a directory, not a regular file"), std::string::npos) << m;
  m = include("zero.inp", "/dev/zero");
  EXPECT_NE(m.find("zero.inp':3: *INCLUDE: INPUT='/dev/zero' (/dev/zero) is a character device"),
            std::string::npos)
      << m;
  m = include("null.inp", "/dev/null");
  EXPECT_NE(m.find("is a character device, not a regular file"), std::string::npos) << m;
  m = format_error_of("/dev/zero");
  EXPECT_EQ(m, "'/dev/zero' is a character device, not a regular file (a deck is read from a regular file)");
  m = format_error_of(dir() / "kinds" / "sub");
  EXPECT_NE(m.find("is a directory, not a regular file"), std::string::npos) << m;
  const fs::path fifo = dir() / "kinds" / "deck.fifo";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  m = format_error_of(fifo);  // without a writer: refused, not waited for
  EXPECT_NE(m.find("is a FIFO (named pipe), not a regular file"), std::string::npos) << m;
  m = include("fifo.inp", "deck.fifo");
  EXPECT_NE(m.find("fifo.inp':3: *INCLUDE: INPUT='deck.fifo'"), std::string::npos) << m;
  EXPECT_NE(m.find("is a FIFO (named pipe), not a regular file"), std::string::npos) << m;
}

TEST(InpDeck, ALineLongerThanAnyDeckNeedsIsAnErrorNamingFileAndLine) {
  // 10 MB on one line (no line end at all): refused at 64 KiB, with the file and the line, not read whole.
  const std::string head = "*NODE\n1, 0, 0, 0\n";
  EXPECT_EQ(error_of<FormatError>("long-line.inp", head + "2, 0, " + std::string(10'000'000, '7') + "\n"),
            location("long-line.inp", 3) +
                " the line is longer than 65536 bytes (Abaqus reads 256 characters a "
                "line): not an input deck");
  EXPECT_NE(error_of<FormatError>("no-line-end.inp", head + std::string(100'000, 'x'))
                .find(location("no-line-end.inp", 3)),
            std::string::npos);
  // A line just within the limit is read (and its field quoted short in the message).
  const std::string field(65'536 - 9, '5');
  const std::string m = error_of<FormatError>("within.inp", head + "2, 0, 0, " + field + "\n");
  EXPECT_EQ(m, location("within.inp", 3) + " *NODE: node 2: field 4: '" + std::string(kQuotedBytes, '5') +
                   "...' (" + std::to_string(field.size()) + " bytes) is not a finite number");
}

TEST(InpDeck, TextThatIsNotADeckIsNamedByItsEncodingOrLineEnds) {
  // They read as a deck without *CONTACT PAIR (exit 2); the encoding or the line ends is what to fix.
  const std::string deck = "*NODE\r\n1, 0, 0, 0\r\n*CONTACT PAIR\r\nA, B\r\n";
  std::string utf16le = "\xFF\xFE", utf16be = "\xFE\xFF", bare16, utf32le("\xFF\xFE\x00\x00", 4);
  for (const char c : deck) {
    utf16le += std::string{c, '\0'};
    utf16be += std::string{'\0', c};
    bare16 += std::string{c, '\0'};
    utf32le += std::string{c, '\0', '\0', '\0'};
  }
  struct Case {
    const char* name;
    std::string text;
    int line;
    const char* says;
  };
  std::string cr_only = "*NODE\r1, 0, 0, 0\r*CONTACT PAIR\rA, B\r";
  std::string long_cr_only;
  while (long_cr_only.size() < 200'000) long_cr_only += "1, 0, 0, 0\r";
  // An HDF5 file's signature: "\x89HDF", CRLF, then 0x1A on the second line.
  const std::string binary("\x89HDF\r\n\x1a\n\x00\x00\x00\x00\x00\x08\x08\x00", 16);
  const std::vector<Case> cases = {
      {"utf16le.inp", utf16le, 1, "the file is UTF-16 (little-endian) text (by its byte-order mark)"},
      {"utf16be.inp", utf16be, 1, "the file is UTF-16 (big-endian) text (by its byte-order mark)"},
      {"utf32le.inp", utf32le, 1, "the file is UTF-32 (little-endian) text (by its byte-order mark)"},
      {"bare-utf16.inp", bare16, 1,
       "column 2: a NUL byte: UTF-16 or UTF-32 text without a byte-order mark, or a binary file"},
      {"cr-only.inp", cr_only, 1,
       "column 6: a carriage return without a line feed (a file with CR-only line ends?)"},
      {"long-cr-only.inp", "*NODE\n" + long_cr_only, 2, "column 11: a carriage return without a line feed"},
      {"binary.inp", binary, 2, "column 1: control character 0x1A: a binary file, not a deck"},
      {"nul-later.inp", "*NODE\n1, 0, 0, 0\n2, 0," + std::string(1, '\0') + " 0, 0\n", 3,
       "column 6: a NUL byte"},
  };
  for (const Case& c : cases) {
    const std::string m = error_of<FormatError>(c.name, c.text);
    EXPECT_NE(m.find(location(c.name, c.line)), std::string::npos) << c.name << ": " << m;
    EXPECT_NE(m.find(c.says), std::string::npos) << c.name << ": " << m;
  }
  // CRLF, tabs and a UTF-8 byte-order mark on an included file are still text.
  write(dir() / "text-inc" / "nodes.inp",
        "\xEF\xBB\xBF"
        "2,\t1, 0, 0\r\n** comment\r\n");
  const auto model = read_inp_deck(
      write(dir() / "text-inc" / "main.inp", "*NODE\r\n1, 0, 0, 0\r\n*INCLUDE, INPUT=nodes.inp\r\n"));
  EXPECT_EQ(model.mesh.node_count(), 2);
}

TEST(InpDeck, UserTextIsQuotedShortInMessages) {
  // Issue: a 10 MB field was copied whole into the message (the CSV reader quoted short, the deck reader
  // not).
  const std::string big(60'000, 'q');
  const std::string head = kNodes + kElements;  // 21 lines
  const std::string shown = "'" + std::string(kQuotedBytes, 'q') + "...' (60000 bytes)";
  const std::vector<BadDeck> cases = {
      {"big-id.inp", "*NODE\n" + big + ", 0, 0, 0\n", 2, "field 1: "},
      {"big-set.inp", head + "*NSET, NSET=A\n1, " + big + "\n", 23, "unknown node set "},
      {"big-face.inp", head + "*SURFACE, NAME=M\nLOWER, " + big + "\n", 23, "field 2: "},
      {"big-surface.inp", head + kSurfaces + "*CONTACT PAIR\nSBOTTOM, " + big + "\n", 27,
       "unknown master surface "},
      {"big-system.inp", "*NODE, SYSTEM=" + big + "\n", 1, "SYSTEM="},
  };
  for (const BadDeck& c : cases) {
    const std::string m = error_of<FormatError>(c.name, c.text);
    EXPECT_NE(m.find(location(c.name, c.line)), std::string::npos) << c.name << ": " << m.substr(0, 300);
    EXPECT_NE(m.find(std::string(c.says) + shown), std::string::npos) << c.name << ": " << m.substr(0, 300);
    EXPECT_LT(m.size(), 400u) << c.name << ": " << m.substr(0, 300);
  }
}

// Issue 39: a deck's bytes that are no text (Latin-1, a binary file's, broken UTF-8) were printed raw in the
// message; they are escaped as \xHH, valid UTF-8 kept.
TEST(InpDeck, MessagesEscapeBytesThatAreNoText) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n";
  const auto expect_escaped = [](const std::string& message, const std::string& shown) {
    EXPECT_NE(message.find(shown), std::string::npos) << message;
    for (const char c : message) {
      const auto b = static_cast<unsigned char>(c);
      EXPECT_TRUE(b >= 0x20 && b < 0x7f) << "a raw byte " << int(b) << " in: " << message;
    }
  };
  expect_escaped(error_of<FormatError>("name.inp", nodes + "*SURFACE, NAME=\xff\xfe"
                                                           "ab\n1, S1\n"),
                 "'\\xff\\xfeab'");
  expect_escaped(error_of<FormatError>("field.inp", "*NODE\n\xe9\xff, 0, 0, 0\n"), "'\\xe9\\xff'");
  expect_escaped(error_of<FormatError>("utf8.inp", nodes + "*ELEMENT, TYPE=C3D8\n1, 1, 2\xc3\x28, 3\n"),
                 "'2\\xc3('");
  // Valid UTF-8 stays as it is.
  const std::string accented = error_of<FormatError>("accent.inp", nodes +
                                                                       "*SURFACE, NAME=Fl\xc3\xa4"
                                                                       "che\n1, S1\n");
  EXPECT_NE(accented.find("'Fl\xc3\xa4"
                          "che'"),
            std::string::npos)
      << accented;
  EXPECT_EQ(quote_text("tab\there\x7f"), "'tab\\x09here\\x7f'");
  EXPECT_EQ(quote_text("\xf0\x9f\x98\x80 \xed\xa0\x80 \xc0\xaf"),
            "'\xf0\x9f\x98\x80 \\xed\\xa0\\x80 \\xc0\\xaf'");
}

}  // namespace
}  // namespace contactnn::io
