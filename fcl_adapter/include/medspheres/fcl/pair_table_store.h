#pragma once
/// \file
/// PairTableStore: a folder of PairJointTable bakes (pair_joint_table.h), one file a table,
/// so that a checker built again for the same robot reads its tables instead of baking them
/// (minutes for large tables, against a fraction of a second to read).
///
/// A table's file is named by its key: the SHA-256 of everything a table's cells are
/// computed from (PairJointTable::build): the robot's kinematic tree (every step's links,
/// type, origin, axis, source, multiplier and offset), the table's joints and their limits,
/// the two links' meshes (vertices and triangles) and sphere trees (every ball), the margin
/// and the cell budget, with the format's version. A robot, mesh or option that differs in
/// any bit has another key, so a table can never be read for a geometry it was not baked
/// for. The file repeats its key and joints, and holds the nodes with their SHA-256; a file
/// that does not parse, is of another format version, whose key or joints differ, whose
/// nodes do not match their digest or do not make a tree is not read (the table is baked
/// again and the file replaced): a damaged file is never read as a table.
///
/// Files: CBOR (nlohmann-json's), written atomically (io.h, write_file_atomically), so that
/// checkers baking the same table at once in several processes leave one whole file.
/// Threads: load() and save() may run from many threads at once.

#include <cstddef>
#include <memory>
#include <string>

namespace medspheres::fcl {

class PairJointTable;

class PairTableStore {
 public:
  /// The store in \p folder, created (with its parents) when missing.
  /// \throws InputError naming the folder when it cannot be created or is not a folder.
  explicit PairTableStore(std::string folder);

  const std::string& folder() const noexcept { return folder_; }
  /// The file of the table of \p key (64 hex digits).
  std::string path(const std::string& key) const;

  /// Reads the stored nodes of \p key into \p table (whose joints, limits and far link
  /// build() has set): false, \p table unchanged, when there is no such file or it is not
  /// that key's table.
  bool load(const std::string& key, PairJointTable& table) const;
  /// Writes \p table as \p key's file, replacing any. \throws Error naming the file when it
  /// cannot be written.
  void save(const std::string& key, const PairJointTable& table) const;
  /// Before a bake whose table is missing: that a file can be written in the folder (one is
  /// written and removed), so that a store that cannot keep the table fails at once, not
  /// after the bake. \throws InputError naming the folder and \p what (the table's pair).
  void require_writable(const std::string& key, const std::string& what) const;

 private:
  std::string folder_;
};

}  // namespace medspheres::fcl
