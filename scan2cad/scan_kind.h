#pragma once
/// What a scan shows. It sets the defaults of reconstruct and repair: a head is closed
/// (every hole is filled), a respirator is an open shell (its rim is kept open).
#include <string>

#include "pipeline/cli.h"
#include "pipeline/read_scan.h"

namespace scan2cad {

enum class ScanKind { head, respirator };

/// Parses "head" or "respirator". @throws pipeline::Error(usage) otherwise.
ScanKind parse_scan_kind(const std::string& name);
std::string scan_kind_name(ScanKind kind);
/// Real largest extent of the object [mm], for unit detection (head 250, respirator 130).
double expected_size_mm(ScanKind kind);

/// The --kind and --unit options shared by the reconstruct and repair programs: registered on
/// a Cli by add_to(), parsed after the command line by kind() and read_options() (the unit is
/// forced, or detected against the kind's expected size).
struct KindAndUnitOptions {
  std::string kind_name = "head", unit_name = "auto";
  /// Adds -k/--kind (described by `kind_help`) and -u/--unit to `cli`.
  void add_to(pipeline::Cli& cli, const std::string& kind_help);
  /// @throws pipeline::Error(usage) on an unknown kind.
  ScanKind kind() const;
  /// @throws pipeline::Error(usage) on an unknown kind or unit.
  pipeline::ScanReadOptions read_options() const;
  /// pipeline::describe_unit for `scan`, read with these options, then the reader's notes.
  std::string describe_unit(const pipeline::Scan& scan) const;
  /// With --unit given, pipeline::require_forced_unit_plausible for `scan`, read from `path`.
  void require_plausible_size(const pipeline::Scan& scan, const std::string& path) const;
};

}  // namespace scan2cad
