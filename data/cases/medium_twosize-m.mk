# Case medium_twosize-m: headform 'medium' with respirator 'twosize-m'.
# Scans default to the generated ones (data/generator); point a case at a real scan by
# uncommenting a line below, or on the command line: make case=medium_twosize-m HEADFORM_SCAN=path.
HEADFORM := medium
RESPIRATOR := twosize-m
# HEADFORM_SCAN := path/to/head_scan.ply
# RESPIRATOR_SCAN := path/to/respirator_scan.ply
# Strap and placement settings [mm] (make help), e.g.: STRAP_LENGTH_MM := 280
