# Case shortwide_onesize: headform 'shortwide' with respirator 'onesize'.
# Scans default to the generated ones (data/generator); point a case at a real scan by
# uncommenting a line below, or on the command line: make case=shortwide_onesize HEADFORM_SCAN=path.
HEADFORM := shortwide
RESPIRATOR := onesize
# HEADFORM_SCAN := path/to/head_scan.ply
# RESPIRATOR_SCAN := path/to/respirator_scan.ply
# Strap and placement settings [mm] (make help), e.g.: STRAP_LENGTH_MM := 280
