// Object sources behind one interface: the embedded meshes, Debian's Sweet Home 3D furniture
// catalogue, and a folder of mesh files (e.g. a ShapeNetCore v2 tree).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "occlusion_env/scene/mesh.hpp"

namespace occlusion_env {

/// What a catalogue knows about one object without loading its mesh.
struct ObjectInfo {
  std::string id;        // unique within its catalogue; looked up, never used as a file path
  std::string name;      // human-readable
  std::string category;  // object type, lower-case singular: "chair", "table", "lamp", "mug", ...
                         // ("other" when the source gives no type)
  std::string source_category;  // the source's own grouping: Sweet Home 3D's room category
                                // ("Living room"), a ShapeNet synset id, a folder name
  std::string creator;          // author to credit where the model is shown
  std::string license;          // e.g. "CC0", "CC-BY 3.0", "BSD-3-Clause (occlusion_env)"
  // Width (along y), depth (along x, front to back) and height (z) [m]; 0 if unknown.
  Eigen::Vector3f dimensions_m = Eigen::Vector3f::Zero();
};

class ObjectCatalog {
 public:
  virtual ~ObjectCatalog() = default;

  /// Short name of the source: "embedded", "sweethome3d" or "folder".
  virtual std::string sourceName() const = 0;

  /// Every object, in a stable order (sorted by id).
  virtual const std::vector<ObjectInfo>& objects() const = 0;

  /// Loads the full-resolution mesh of `id`, converted to z up with the object's front facing +x.
  /// Not normalised. Throws InvalidArgumentError for an unknown id, CatalogError naming the file
  /// when its data cannot be read.
  virtual Mesh loadMesh(const std::string& id) const = 0;

  /// nullptr when `id` is unknown.
  const ObjectInfo* find(const std::string& id) const;
  /// Ids of the objects in `category` (sorted); empty when none.
  std::vector<std::string> idsInCategory(const std::string& category) const;
  /// Distinct categories, sorted.
  std::vector<std::string> categories() const;
};

/// Where objects come from; see config/sim.yaml for the documented parameters.
struct CatalogOptions {
  std::string source = "embedded";  // embedded | sweethome3d | folder
  /// sweethome3d: `.sh3f` files or folders holding them (empty: Debian's installed catalogues).
  /// folder: one root folder, searched recursively for .obj/.ply/.glb/.gltf/.off/.stl files.
  std::vector<std::string> paths;
};

/// The project's own procedurally built meshes (no external data).
std::unique_ptr<ObjectCatalog> makeEmbeddedCatalog();

/// Reads `.sh3f` catalogues (zip + PluginFurnitureCatalog.properties). Throws CatalogError naming
/// the file when one cannot be opened or parsed.
std::unique_ptr<ObjectCatalog> makeSweetHome3DCatalog(const std::vector<std::string>& paths);

/// The `.sh3f` files Debian's sweethome3d-furniture package installs (empty if not installed).
std::vector<std::string> defaultSweetHome3DCatalogPaths();

/// Every mesh file below `root`. In a ShapeNetCore v2 tree (`<synset>/<model>/models/
/// model_normalized.obj`) the id is `<synset>/<model>` and the category is the synset's name;
/// elsewhere the id is the path relative to root and the category the parent folder's name.
std::unique_ptr<ObjectCatalog> makeMeshFolderCatalog(const std::string& root);

/// Builds the catalogue `options` describe. Throws InvalidArgumentError for an unknown source.
std::unique_ptr<ObjectCatalog> makeCatalog(const CatalogOptions& options);

}  // namespace occlusion_env
