# Case medium_threesize-s: headform 'medium' with respirator 'threesize-s'.
# Scans default to the generated ones (data/generator); point a case at a real scan by
# uncommenting a line below, or on the command line: make case=medium_threesize-s HEADFORM_SCAN=path.
HEADFORM := medium
RESPIRATOR := threesize-s
# HEADFORM_SCAN := path/to/head_scan.ply
# RESPIRATOR_SCAN := path/to/respirator_scan.ply
# Strap and placement settings [mm] (make help), e.g.: STRAP_LENGTH_MM := 280
