"""read_mesh_or_raise(path, file_format=None): meshio.read that raises ValueError instead of exiting.

Input:  path of a mesh file meshio reads (MSH, STL, PLY, OFF, OBJ, VTU, ...); file_format as for
        meshio.read (None: from the extension).
Output: the meshio.Mesh.
Raises: OSError when the file is missing or cannot be opened; ValueError, with meshio's own
        message, when it is not a mesh in that format or meshio fails inside its reader (meshio
        raises its own ReadError for a missing file or an unknown extension, and IndexError on a
        binary PLY with a face property, e.g. segment's part label).

Why: meshio 5.0 (Debian 12) prints to stdout and stderr and calls sys.exit(1) when a file is not
in the format its extension names, so `except Exception` in a script never sees it and the user
gets two stray lines instead of one naming the script and the file. The project's Python tools
import this instead of calling meshio.read.
"""
import contextlib
import errno
import io
import os

import meshio


def read_mesh_or_raise(path, file_format=None):
    if not os.path.isfile(path):
        raise FileNotFoundError(errno.ENOENT, "no such file" if not os.path.exists(path) else "not a file", path)
    with open(path, "rb"):
        pass  # unreadable: the OSError says why
    captured = io.StringIO()
    try:
        with contextlib.redirect_stdout(captured), contextlib.redirect_stderr(captured):
            return meshio.read(path, file_format=file_format)
    except meshio.ReadError as e:
        raise ValueError(str(e)) from None
    except (IndexError, KeyError) as e:
        hint = ("; Debian's meshio 5.0 cannot read a binary PLY with a face property (such as segment's part label)"
                if path.lower().endswith(".ply") else "")
        raise ValueError(f"meshio's reader failed ({type(e).__name__}: {e}){hint}") from None
    except SystemExit:
        lines = [line.strip() for line in captured.getvalue().splitlines() if line.strip()]
        message = lines[-1].removeprefix("Error: ") if lines else "meshio could not read it"
        raise ValueError(message) from None
