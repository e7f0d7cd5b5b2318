#pragma once
// What the mesh readers (OBJ, TetGen, Gmsh) share for reading text.
#include <string>

namespace sinew {

// The whole file; InputError "PATH: cannot open file for reading" / "cannot read file".
std::string read_whole_file(const std::string& path);

// Blank within a line (the readers split lines on '\n' themselves).
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

}  // namespace sinew
