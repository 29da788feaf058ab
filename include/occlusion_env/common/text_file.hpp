// Text files the tools write (results, logs, run state): a file that cannot be written is an error
// that names it and the reason, never a result that silently went nowhere.
#pragma once

#include <string>

namespace occlusion_env {

/// Writes `text` to `path`, replacing the file. Throws std::runtime_error naming `path` and the
/// reason (no such directory, no permission, disk full) when the file cannot be written.
void writeTextFile(const std::string& path, const std::string& text);

/// Appends `text` to `path` (created if missing); throws as writeTextFile.
void appendTextFile(const std::string& path, const std::string& text);

/// Writes `text` to `path` + ".tmp" and renames it to `path`: a reader (a run resuming from its
/// state) finds the old file or the whole new one, never a part. Throws as writeTextFile.
void replaceTextFile(const std::string& path, const std::string& text);

}  // namespace occlusion_env
