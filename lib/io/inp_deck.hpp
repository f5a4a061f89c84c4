// Abaqus / CalculiX input decks (.inp): the subset that carries a contact pair (SPEC 7).
//
// Read: *NODE (NSET=; SYSTEM=R only), *ELEMENT (TYPE=, ELSET=), *NSET / *ELSET (GENERATE; ids and names of
// sets defined earlier; *NSET, ELSET= takes the nodes of an element set), *SURFACE (TYPE=ELEMENT, the
// default: element id or element set, then S1..S6; TYPE=NODE: node id or node set), *CONTACT PAIR (each
// data line "slave, master"; TYPE= NODE TO SURFACE, CalculiX's default, or another), *INCLUDE, INPUT=
// (relative to the including file; the included lines take the place of the *INCLUDE line, so they may
// continue the data of the keyword before it). INPUT= on *NODE, *ELEMENT, *NSET, *ELSET reads that
// keyword's data lines from the file. *TIE, CYCLIC SYMMETRY (NAME=; "dependent, independent") and *CYCLIC
// SYMMETRY MODEL (N=, TIE=, optional with one cyclic tie; the axis line "ax, ay, az, bx, by, bz"): the
// model's sectors (mesh::CyclicSymmetry). Every other keyword (other *TIE cards too) is skipped with its
// data lines.
//
// Lexical rules: keywords, parameter names and values, and set / surface names are case-insensitive
// (blanks inside keywords are ignored: "*Contact Pair" = "*CONTACTPAIR"); a line starting "**" is a comment;
// fields are comma-separated, blanks and tabs around them ignored, empty fields ignored (trailing commas);
// CRLF line ends and a UTF-8 byte-order mark are accepted; numbers may use a Fortran D exponent. Files are
// streamed (one line of each open file in memory). An element
// whose type has a known node count (mesh::element_type) takes data lines until it has that many nodes
// (C3D20 spans two lines); an element of another type continues while its line ends with a comma.
// Repeated *NSET / *ELSET / *SURFACE of one name (and type) add to it.
//
// Names: a node surface and an element surface may share a name (surfaces are keyed by name and type).
// A pair's slave is the node surface of that name if the pair is NODE TO SURFACE and one exists, else the
// element surface, else the node surface; its master is the element surface of that name, else (an error
// when the pair is used, mesh::master_surface) the node surface.
//
// Errors: FormatError (exit 3) "'FILE':LINE: *KEYWORD: ..." naming the field for anything malformed: a
// field that is not a number or id, a non-finite coordinate, a node id defined twice with other
// coordinates (both lines named), an element defined twice differently, an element with too many or too
// few nodes or an undefined node, a missing TYPE= or NAME=, an unknown set, surface or element name, a
// face label that is not S1..S<faces of the element>, a bad GENERATE range, a *CONTACT PAIR line that is
// not two names, an *INCLUDE that includes itself (the chain named), a cyclic symmetry model without N=,
// axis line or tie (or naming an unknown one); text that is not a deck, named by what gives it away: a
// UTF-16 or UTF-32 byte-order mark, a NUL byte (UTF-16 without a mark, or a binary file), a carriage return
// inside a line (CR-only line ends), another control character, a line longer than 64 KiB (Abaqus reads 256
// characters a line); a deck or *INCLUDE that is not a regular file (a directory, a device such as /dev/zero,
// a FIFO). User text in messages (fields, names) is quoted with quote_text (at most 40 bytes). IoError (exit
// 4) naming the file for a deck or included file that cannot be opened or read.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/contact_model.hpp"

namespace contactnn::io {

/// Reads the deck at `path` (and the files it includes).
[[nodiscard]] mesh::ContactModel read_inp_deck(const std::filesystem::path& path);

/// Same, from text in memory; `name` stands for the file in messages and its directory resolves includes.
[[nodiscard]] mesh::ContactModel parse_inp_deck(std::string_view text, const std::filesystem::path& name);

/// The keywords of the deck at `path` (and of the files it includes, *INCLUDE, INPUT=) that change the
/// contact geometry CalculiX uses and that the project does not apply (the reader skips them): *CLEARANCE (a
/// gap set in place of the mesh's), *CONTACT PAIR with ADJUST= (slave nodes moved onto the master), *CONTACT
/// INTERFERENCE (an overclosure), *SHELL SECTION with OFFSET= (a shell's surface moved off its nodes). One
/// entry per keyword line, "'FILE':LINE: *KEYWORD ..." with the line's text escaped and cut at 80 bytes, in
/// file order. A file that cannot be read is skipped (read_inp_deck reports it).
[[nodiscard]] std::vector<std::string> unapplied_geometry_keywords(const std::filesystem::path& path);

}  // namespace contactnn::io
