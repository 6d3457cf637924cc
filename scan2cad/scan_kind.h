#pragma once
/// What a scan shows. It sets the defaults of reconstruct and repair: a head is closed
/// (every hole is filled), a respirator is an open shell (its rim is kept open).
#include <string>

namespace scan2cad {

enum class ScanKind { head, respirator };

/// Parses "head" or "respirator". @throws pipeline::Error(usage) otherwise.
ScanKind parse_scan_kind(const std::string& name);
std::string scan_kind_name(ScanKind kind);
/// Real largest extent of the object [mm], for unit detection (head 250, respirator 130).
double expected_size_mm(ScanKind kind);

}  // namespace scan2cad
