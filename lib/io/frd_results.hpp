// CalculiX's ASCII result file (.frd): the node block, the DISP of each increment and the CONTACT state
// of the slave nodes (SPEC 10).
//
// The format is fixed-column (CalculiX GraphiX manual, "Result Format"; ccx 2.20 src/frd.c, frdheader.c):
//   "    1C", "    1U..."                     model and user headers (skipped)
//   "    2C" ... NUMNOD (cols 25-36), FORMAT (col 74): the node block, then one " -1" record per node:
//            short format (FORMAT 0): (1X,'-1',I5,3E12.5)   long format (FORMAT 1, what ccx writes):
//            (1X,'-1',I10,3E12.5), then " -3"
//   "    3C"                                  the element block (skipped up to its " -3")
//   "    1PSTEP" ... INCREMENT (cols 37-48), STEP (cols 49-60): a parameter record; ccx writes one before
//            every result block (other "1P" records are skipped)
//   "  100C" VALUE (cols 13-24, the time), NUMNOD (25-36), ICTYPE (57-58: 0 static, 1 dynamic, 2 frequency,
//            3 other, 4 buckling), NUMSTP (59-63: ccx's running count of its outputs), FORMAT (74-75):
//            a result block; then " -4  NAME  NCOMPS IRTYPE", one " -5  NAME ..." per component (IEXIST in
//            cols 34-38; 1 marks a component the reader computes, such as DISP's ALL, with no value in the
//            records), the value records " -1" node id then up to 6 values (E12.5, ids I5 or I10 by
//            FORMAT), " -2" continuation records for the 7th value on, and " -3"
//   " 9999"                                   end of data (optional: a run that stopped early has none)
// Values are read by column, never by blank (ccx writes "-1.61361E-04-1.61361E-04" with no blank between).
// A blank integer or value field of a header record reads as 0, as Fortran reads it.
//
// Increments (SPEC 10): the result blocks named DISP of static (ICTYPE 0) or dynamic (ICTYPE 1: *DYNAMIC,
// *STEADY STATE DYNAMICS) steps, counted from 1 in file order; DISP of frequency and buckling steps (mode
// shapes) does not count. The CONTACT blocks (COPEN, CSLIP1, CSLIP2, CPRESS, CSHEAR1, CSHEAR2; ccx 2.20
// writes all six for *CONTACT FILE CDIS or CSTR alike) belong to the increment whose DISP block has the same
// step and NUMSTP. Other result blocks (STRESS, ENER, ...) are skipped, but must end with " -3".
//
// Errors: FormatError (exit 3) "'FILE':LINE: <record or block>: ..." naming what was expected for: a record
// key that is not one of the above, a field that is not a number (columns named), a non-finite value, a
// record too short for its values or with text after them, a block that ends (another record or the end
// of the file) without its " -3", a result header not followed by " -4" or a " -4" announcing another
// number of components than " -5" records follow, a node id given twice in the node block or in one DISP
// block, a second node block, a binary block (FORMAT 2 or 3), a DISP block without D1, D2, D3 or a CONTACT
// block without COPEN, CSLIP1, CSLIP2; a file with no node block or no DISP of a static or dynamic step (the
// line is then the file's last); a directory. IoError (exit 4) if the file cannot be read.
// Limits: ASCII only; one node block (a mesh that changes during the run is refused); each increment's
// DISP is held in memory (nodes x increments x 32 bytes).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/surface_point.hpp"
#include "mesh/contact_model.hpp"
#include "mesh/solid_mesh.hpp"

namespace contactnn::io {

/// CalculiX's contact state of one slave node at one increment (a CONTACT block's record). COPEN < 0 is
/// penetration (length units of the deck); CSLIP1, CSLIP2 the tangential relative displacements; CPRESS,
/// CSHEAR1, CSHEAR2 the contact stresses (has_stress: the block held CPRESS, CSHEAR1 and CSHEAR2).
struct FrdContact {
  long node = 0;
  double copen = 0, cslip1 = 0, cslip2 = 0;
  bool has_stress = false;
  double cpress = 0, cshear1 = 0, cshear2 = 0;
};

/// One increment of SPEC 10: a DISP block of a static or dynamic step, with its contact state.
struct FrdIncrement {
  int number = 0;                ///< SPEC 10's N: 1-based, in file order (increments[i].number == i + 1)
  int step = 0;                  ///< STEP of the last "1PSTEP" record before the block (0 if none)
  int increment_in_step = 0;     ///< INCREMENT of that record (0 if none)
  int analysis_type = 0;         ///< the header's ICTYPE: 0 static, 1 dynamic
  int output_counter = 0;        ///< the header's NUMSTP (ccx counts its outputs over the whole run)
  double time = 0.0;             ///< the header's VALUE: the total time of the increment
  int line = 0;                  ///< line of the DISP block's "  100C" header in the file
  std::vector<long> disp_nodes;  ///< node ids of the DISP records, file order
  std::vector<geometry::Vec3> displacement;  ///< (D1, D2, D3) of disp_nodes, same order
  std::vector<FrdContact> contact;  ///< the increment's CONTACT records, stable-sorted by node id (a node
                                    ///< in two contact pairs appears twice); empty if none
};

struct FrdResults {
  std::string file;                         ///< the path as given, for messages
  int node_block_line = 0;                  ///< line of the "    2C" header
  std::vector<long> node_ids;               ///< the node block, file order
  std::vector<geometry::Vec3> coordinates;  ///< same order: the coordinates the solver used
  std::vector<FrdIncrement> increments;     ///< SPEC 10's increments, never empty
};

/// Reads the .frd at `path`. Throws as the header comment says.
[[nodiscard]] FrdResults read_frd(const std::string& path);

/// `number` for SPEC 10's "--increment last".
inline constexpr int kLastIncrement = -1;

/// Index into results.increments of SPEC 10's N (1-based), or of the last for kLastIncrement.
/// InvalidArgument (exit 2) naming the file and its number of increments when N is out of range.
[[nodiscard]] std::size_t increment_index(const FrdResults& results, int number);

/// How far (in units of the model's size) a node of the node block may lie from the deck's node of that id.
inline constexpr double kNodeBlockTolerance = 1e-3;

/// Checks that `results` is a run of `model`'s mesh and not of another mesh with the same node ids (scaled,
/// rotated, moved), before the tools move any node (their --trust-results-nodes skips it): every node of the
/// deck's elements that the node block lists must lie where the deck puts it (mesh.deck_position), within
/// kNodeBlockTolerance of the model's size (the diagonal of the box around those nodes) plus the block's
/// rounding (E12.5: 1e-5 of the coordinate). Nodes of the contact pairs' slave surfaces are not checked:
/// *CONTACT PAIR, ADJUST= moves them before CalculiX writes the node block (punch1.inp of its test suite:
/// 0.0043). FormatError (exit 3) naming the file, the node block's line, the first node that differs, both
/// positions, the distance, the tolerance and --trust-results-nodes. Nodes the block lacks are left to
/// move_to_increment.
void check_node_block(const mesh::ContactModel& model, const FrdResults& results);

/// Moves every node of `mesh` to its node-block coordinates plus the DISP of results.increments[increment].
/// A node used by no element of `mesh` may be absent from the node block or from DISP (ccx leaves such nodes
/// out): it keeps its position (its node-block coordinates, if listed). A node used by an element must be
/// in both, else FormatError naming the results file and the line of the node block (the results do not
/// belong to the deck) or of the DISP block (U written for a node set only: "*NODE FILE, NSET="), the node,
/// an element using it and how many nodes are missing; `mesh` is then left unchanged. When the element using
/// the first missing node is not a solid (C3D*: a shell, beam, membrane or plane element), the message says
/// what CalculiX did instead: it writes the expanded 3-D nodes of such elements under new ids (counted: the
/// node block's nodes the deck does not have), which the project does not model.
/// InvalidArgument if `increment` is out of range.
void move_to_increment(mesh::SolidMesh& mesh, const FrdResults& results, std::size_t increment);

/// Where `results` holds each node of a mesh at one increment: its row of the node block
/// (results.node_ids) and of the increment's DISP (disp_nodes), -1 where it has none; indexed by SolidMesh
/// node index.
struct NodeRows {
  std::vector<long> block, disp;
};

/// The rows of every node of `mesh` in `results` and its increment `increment`, after move_to_increment's
/// checks (the same errors: every node an element uses is in both). They depend only on the mesh, the node
/// block and the increment's disp_nodes: an increment that lists the same DISP nodes in the same order has
/// the same rows (history::RunStates looks them up once for a run whose increments all do).
[[nodiscard]] NodeRows node_rows(const mesh::SolidMesh& mesh, const FrdResults& results,
                                 std::size_t increment);

/// Node n's position at increment `inc` of `results` by `rows` (node_rows of that increment, or of one with
/// the same disp_nodes): its node-block coordinates plus its DISP, as move_to_increment places it. Only for a
/// node with a node-block row.
[[nodiscard]] inline geometry::Vec3 position_at(const FrdResults& results, const FrdIncrement& inc,
                                                const NodeRows& rows, int n) {
  const auto u = static_cast<std::size_t>(n);
  geometry::Vec3 p = results.coordinates[static_cast<std::size_t>(rows.block[u])];
  if (rows.disp[u] >= 0) p += inc.displacement[static_cast<std::size_t>(rows.disp[u])];
  return p;
}

}  // namespace contactnn::io
