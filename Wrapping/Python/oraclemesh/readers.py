# SPDX-License-Identifier: GPL-3.0-or-later
"""Readers chosen by file extension, for surfaces and label maps.

Surfaces (``.vtp .vtk .stl .obj .ply``) go through VTK's readers and are taken as they are, in the
scene's coordinates. Label maps (``.vti .mha .mhd .nii .nii.gz .nrrd .nhdr .inr .inr.gz``) are placed
in the scene with their origin, spacing and direction, and converted to the scene's anatomical frame (``space``:
``LPS``, the default, as ITK and 3D Slicer's files use, or ``RAS``):

- ``.vti``: origin, spacing and direction as stored, no anatomical frame;
- MetaImage ``.mha/.mhd``: ``Offset``, ``ElementSpacing``, ``TransformMatrix`` (ITK's order: the
  direction of axis i is its i-th triple), LPS (VTK's reader ignores the direction: it is applied here);
- NIfTI ``.nii/.nii.gz``: the sform when its code is set, else the qform, else the spacing alone;
  NIfTI's world is RAS (VTK's reader leaves the matrices aside: they are applied here);
- NRRD ``.nrrd/.nhdr``: read here (VTK 9.2's vtkNrrdReader misreads 3-D volumes): ``space origin``,
  ``space directions`` (or ``spacings``), the frame from ``space``; raw, gzip, bzip2 or ASCII data;
- INRIMAGE ``.inr/.inr.gz`` (CGAL's format): ``VX VY VZ`` spacing, ``TX TY TZ`` origin (CGAL's
  Image_3 translation), no direction and no anatomical frame.
"""
import functools
import os
import re
import struct

from .errors import OracleMeshError

SURFACE_EXTENSIONS = (".vtp", ".vtk", ".stl", ".obj", ".ply")
LABEL_MAP_EXTENSIONS = (".vti", ".mha", ".mhd", ".nii", ".nii.gz", ".nrrd", ".nhdr", ".inr", ".inr.gz")
SPACES = ("LPS", "RAS")


def _extension(path):
    lower = path.lower()
    for double in (".nii.gz", ".inr.gz"):
        if lower.endswith(double):
            return double
    return os.path.splitext(lower)[1]


def surface_reader(path):
    """A VTK reader algorithm for a surface or polyline file (.vtp .vtk .stl .obj .ply)."""
    ext = _extension(path)
    if ext == ".vtp":
        from vtkmodules.vtkIOXML import vtkXMLPolyDataReader as Reader
    elif ext == ".vtk":
        from vtkmodules.vtkIOLegacy import vtkPolyDataReader as Reader
    elif ext == ".stl":
        from vtkmodules.vtkIOGeometry import vtkSTLReader as Reader
    elif ext == ".obj":
        from vtkmodules.vtkIOGeometry import vtkOBJReader as Reader
    elif ext == ".ply":
        from vtkmodules.vtkIOPLY import vtkPLYReader as Reader
    else:
        raise OracleMeshError(f"{path}: unknown surface format '{ext}' (use one of {', '.join(SURFACE_EXTENSIONS)})")
    _check_exists(path)
    _check_surface_file(path, ext)
    reader = Reader()
    reader.SetFileName(path)
    if ext == ".stl":
        reader.MergingOn()  # STL repeats every corner: merge them or the surface is all open edges
    return reader


def label_map_reader(path, space="LPS"):
    """An algorithm whose output is the label image of `path` placed in the scene's frame `space`
    (see the module's documentation)."""
    ext = _extension(path)
    if ext not in LABEL_MAP_EXTENSIONS:
        raise OracleMeshError(f"{path}: unknown label-map format '{ext}' (use one of {', '.join(LABEL_MAP_EXTENSIONS)})")
    if space not in SPACES:
        raise OracleMeshError(f"{path}: unknown space {space!r} (use LPS or RAS)")
    _check_exists(path)
    _check_label_map_file(path, ext)
    if ext == ".vti":
        from vtkmodules.vtkIOXML import vtkXMLImageDataReader

        reader = vtkXMLImageDataReader()
        reader.SetFileName(path)
        return reader
    if ext in (".nrrd", ".nhdr"):
        return _ArrayReader(path, space, read_nrrd)
    if ext in (".inr", ".inr.gz"):
        return _ArrayReader(path, space, read_inrimage)
    if ext in (".mha", ".mhd"):
        from vtkmodules.vtkIOImage import vtkMetaImageReader

        reader = vtkMetaImageReader()
        placement = _metaimage_placement
    else:
        from vtkmodules.vtkIOImage import vtkNIFTIImageReader

        reader = vtkNIFTIImageReader()
        placement = _nifti_placement
    reader.SetFileName(path)
    return _Placed(reader, lambda: placement(path, reader), space)


# ---------------------------------------------------------------------------------------------------
# Frames the files declare (for the scene's warnings; nothing is converted by them).

_SLICER_SPACE = re.compile(rb"SPACE\s*=\s*(LPS|RAS)\b", re.IGNORECASE)


def surface_frame(path):
    """The anatomical frame a surface file declares, as 3D Slicer writes it into the header
    ("SPACE=LPS" or "SPACE=RAS": a .vtk's title line, an STL's 80-byte header, a PLY or OBJ comment,
    a .vtp's first kilobyte); None when it declares none. Surfaces are never converted: a declared
    frame only lets the scene warn when it differs from the label maps'."""
    try:
        with open(path, "rb") as f:
            head = f.read(1024)
    except OSError:
        return None
    match = _SLICER_SPACE.search(head)
    return match.group(1).decode().upper() if match else None


def label_map_frame(path):
    """The anatomical frame of a label-map file's world before conversion to the scene's: RAS for
    NIfTI, LPS for MetaImage (ITK's), NRRD's ``space``; None for .vti and .inr (no frame) or a
    header that cannot be read (the reader reports that)."""
    ext = _extension(path)
    if ext in (".nii", ".nii.gz"):
        return "RAS"
    if ext in (".mha", ".mhd"):
        return "LPS"
    if ext in (".nrrd", ".nhdr"):
        try:
            with open(path, "rb") as f:
                head = f.read(65536)
        except OSError:
            return None
        for line in head.split(b"\n\n")[0].decode("latin-1").splitlines():
            key, sep, value = line.partition(":")
            if sep and key.strip().lower() == "space":
                return _NRRD_SPACES.get(value.strip().lower())
    return None


def _check_exists(path):
    if os.path.isdir(path):
        raise OracleMeshError(f"{path}: is a folder, not a file")
    if not os.path.isfile(path):
        raise OracleMeshError(f"{path}: file not found")
    if os.path.getsize(path) == 0:
        raise OracleMeshError(f"{path}: the file is empty (0 bytes)")


# ---------------------------------------------------------------------------------------------------
# Checks before a reader runs: VTK's readers crash on some truncated files (PLY), read others
# silently short (binary STL, MetaImage) or allocate what a header asks for (1e14 voxels).

def available_memory():
    """Bytes this process can still allocate: MemAvailable, capped by the address-space limit."""
    import resource

    available = None
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    available = float(line.split()[1]) * 1024
                    break
    except OSError:
        pass
    if available is None:
        try:
            available = float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
        except (ValueError, OSError):
            available = 1e18
    soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    if soft != resource.RLIM_INFINITY:
        available = min(available, float(soft))
    return available


def _size_text(count):
    for unit in ("bytes", "KB", "MB", "GB", "TB", "PB", "EB"):
        if count < 1024 or unit == "EB":
            return f"{count:.0f} {unit}" if unit == "bytes" else f"{count:.1f} {unit}"
        count /= 1024.0


def check_memory(path, what, voxels, bytes_each):
    """Refuses a label map whose voxels would not fit: the image (bytes_each - 6) and the oracle's
    copy and index (6 bytes a voxel)."""
    needed, available = float(voxels) * bytes_each, available_memory()
    if needed > available:
        raise OracleMeshError(f"{path}: {what} = {float(voxels):.3g} voxels would need {_size_text(needed)} of "
                              f"memory ({bytes_each} bytes each, with the oracle's copy); "
                              f"{_size_text(available)} available")


def _truncated(path, detail):
    return OracleMeshError(f"{path}: the file is truncated: {detail}")


def _check_surface_file(path, ext):
    size = os.path.getsize(path)
    if ext == ".stl":
        with open(path, "rb") as f:
            head = f.read(84)
            f.seek(max(0, size - 512))
            tail = f.read()
        binary_size = 84 + 50 * struct.unpack("<I", head[80:84])[0] if len(head) == 84 else None
        if binary_size == size:
            return
        if head.lstrip().lower().startswith(b"solid") and b"facet" in head + tail:
            if b"endsolid" not in tail.lower():
                raise _truncated(path, "an ASCII STL without 'endsolid' at the end")
            return
        if binary_size is None:
            raise _truncated(path, f"{size} bytes, less than a binary STL's 84-byte header")
        if size < binary_size:
            raise _truncated(path, f"{size} bytes; the binary STL header's {(binary_size - 84) // 50} triangles "
                                   f"need {binary_size}")
    elif ext == ".ply":
        _check_ply(path, size)
    elif ext == ".vtp":
        _check_xml(path, size)


_PLY_SIZES = {"char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2, "int16": 2, "uint16": 2,
              "int": 4, "uint": 4, "int32": 4, "uint32": 4, "float": 4, "float32": 4, "double": 8, "float64": 8}


def _check_ply(path, size):
    with open(path, "rb") as f:
        head = f.read(65536)
    if not head.startswith(b"ply"):
        raise OracleMeshError(f"{path}: not a PLY file (no 'ply' magic)")
    end = head.find(b"end_header")
    if end < 0:
        raise _truncated(path, "the PLY header has no 'end_header'")
    body_start = head.find(b"\n", end) + 1 or len(head)
    elements, fmt = [], "ascii"
    for line in head[:end].decode("latin-1").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "format" and len(words) > 1:
            fmt = words[1]
        elif words[0] == "element" and len(words) == 3:
            try:
                elements.append([words[1], int(words[2]), 0])
            except ValueError:
                raise OracleMeshError(f"{path}: bad PLY header line {line!r}") from None
        elif words[0] == "property" and elements:
            # minimal bytes per item: a list counts its length field and 3 entries (a triangle)
            if len(words) >= 5 and words[1] == "list":
                elements[-1][2] += _PLY_SIZES.get(words[2], 1) + 3 * _PLY_SIZES.get(words[3], 4)
            else:
                elements[-1][2] += _PLY_SIZES.get(words[1], 1)
    if fmt == "ascii":
        with open(path, "rb") as f:
            f.seek(body_start)
            lines = sum(1 for line in f if line.strip())
        needed = sum(count for _, count, _ in elements)
        if lines < needed:
            raise _truncated(path, f"{lines} data lines after the PLY header, which announces {needed}")
    else:
        needed = sum(count * each for _, count, each in elements)
        if size - body_start < needed:
            described = ", ".join(f"{count} {name}" for name, count, _ in elements)
            raise _truncated(path, f"{size - body_start} bytes after the PLY header, which announces "
                                   f"{described} (at least {needed} bytes)")


def _check_xml(path, size):
    with open(path, "rb") as f:
        head = f.read(4096)
        f.seek(max(0, size - 1024))
        tail = f.read()
    if b"<VTKFile" not in head:
        raise OracleMeshError(f"{path}: not a VTK XML file (no <VTKFile> element)")
    if b"</VTKFile>" not in tail:
        raise _truncated(path, "the VTK XML file does not end with </VTKFile>")
    return head


_META_SIZES = {"MET_CHAR": 1, "MET_UCHAR": 1, "MET_SHORT": 2, "MET_USHORT": 2, "MET_INT": 4, "MET_UINT": 4,
               "MET_LONG": 4, "MET_ULONG": 4, "MET_LONG_LONG": 8, "MET_ULONG_LONG": 8, "MET_FLOAT": 4,
               "MET_DOUBLE": 8}
_NIFTI_SIZES = {2: 1, 4: 2, 8: 4, 16: 4, 64: 8, 256: 1, 512: 2, 768: 4, 1024: 8, 1280: 8}


def _check_label_map_file(path, ext):
    import gzip
    import re

    size = os.path.getsize(path)
    if ext == ".vti":
        head = _check_xml(path, size)
        match = re.search(rb'WholeExtent="([^"]*)"', head)
        if match:
            try:
                e = [int(v) for v in match.group(1).split()]
                voxels = (e[1] - e[0] + 1) * (e[3] - e[2] + 1) * (e[5] - e[4] + 1)
            except (ValueError, IndexError):
                raise OracleMeshError(f"{path}: bad WholeExtent {match.group(1).decode('latin-1')!r}") from None
            check_memory(path, f"WholeExtent {match.group(1).decode('latin-1')}", voxels, 1 + 6)
    elif ext in (".mha", ".mhd"):
        header = _metaimage_header(path)
        try:
            dims = [int(v) for v in header.get("DimSize", "").split()]
        except ValueError:
            dims = []
        if not dims:
            raise OracleMeshError(f"{path}: MetaImage header has no valid DimSize")
        each = _META_SIZES.get(header.get("ElementType", "MET_UCHAR"), 1) * int(header.get("ElementNumberOfChannels", "1"))
        voxels = 1
        for d in dims:
            voxels *= d
        check_memory(path, f"DimSize {' x '.join(map(str, dims))}", voxels, each + 6)
        data_file = header.get("ElementDataFile", "LOCAL")
        compressed = header.get("CompressedData", "False").lower() == "true"
        if data_file == "LOCAL":
            with open(path, "rb") as f:
                blob = f.read(65536)
            at = blob.find(b"ElementDataFile")
            start = blob.find(b"\n", at) + 1 if at >= 0 else size
            available = size - start
        elif os.path.isfile(os.path.join(os.path.dirname(path), data_file)):
            available = os.path.getsize(os.path.join(os.path.dirname(path), data_file))
        else:
            raise OracleMeshError(f"{path}: its data file {data_file} is missing")
        expected = int(header["CompressedDataSize"]) if compressed and "CompressedDataSize" in header else \
            (None if compressed else voxels * each)
        if expected is not None and available < expected:
            raise _truncated(path, f"{available} bytes of voxel data, DimSize and ElementType need {expected}")
    elif ext in (".nii", ".nii.gz"):
        try:
            with (gzip.open(path, "rb") if ext == ".nii.gz" else open(path, "rb")) as f:
                header = f.read(352)
        except (OSError, EOFError) as e:
            raise _truncated(path, f"the compressed NIfTI header cannot be read ({e})") from None
        if len(header) < 348:
            raise _truncated(path, f"{len(header)} bytes, less than the 348-byte NIfTI header")
        for order in "<>":
            if struct.unpack(order + "i", header[:4])[0] == 348:
                break
        else:
            raise OracleMeshError(f"{path}: not a NIfTI-1 file (sizeof_hdr is not 348)")
        dim = struct.unpack(order + "8h", header[40:56])
        datatype = struct.unpack(order + "h", header[70:72])[0]
        offset = struct.unpack(order + "f", header[108:112])[0]
        if not 1 <= dim[0] <= 7 or any(d < 0 for d in dim[1:dim[0] + 1]):
            raise OracleMeshError(f"{path}: bad NIfTI dim {list(dim)}")
        voxels = 1
        for d in dim[1:dim[0] + 1]:
            voxels *= max(d, 1)
        each = _NIFTI_SIZES.get(datatype, 8)
        check_memory(path, f"dim {' x '.join(map(str, dim[1:dim[0] + 1]))}", voxels, each + 6)
        if ext == ".nii" and size < int(offset) + voxels * each:
            raise _truncated(path, f"{size} bytes; the NIfTI header's dim and datatype need "
                                   f"{int(offset) + voxels * each}")


# ---------------------------------------------------------------------------------------------------
# Placement: (origin, spacing, direction 3x3 row-major, frame) of a file; applied by _Placed.

def _to_space(origin, direction, frame, space):
    """Converts a placement from the file's anatomical frame to the scene's (LPS <-> RAS negates x and y)."""
    import numpy as np

    if frame is None or frame == space:
        return origin, direction
    flip = np.diag([-1.0, -1.0, 1.0])
    return flip @ origin, flip @ direction


def _metaimage_header(path):
    fields = {}
    with open(path, "rb") as f:
        for raw in f:
            line = raw.decode("latin-1").strip()
            key, sep, value = line.partition("=")
            if not sep:
                continue
            fields[key.strip()] = value.strip()
            if key.strip() == "ElementDataFile":
                break
    return fields


def _numbers(path, text, n, what):
    try:
        values = [float(v) for v in text.replace(",", " ").split()]
    except ValueError:
        values = []
    if len(values) != n:
        raise OracleMeshError(f"{path}: {what} must be {n} numbers, got {text!r}")
    return values


def _metaimage_placement(path, reader):
    import numpy as np

    header = _metaimage_header(path)
    if header.get("NDims", "3").strip() != "3":
        raise OracleMeshError(f"{path}: a label map must be a 3-D image (NDims = {header.get('NDims')})")
    origin = np.array(_numbers(path, header.get("Offset", header.get("Position", "0 0 0")), 3, "Offset"))
    spacing = np.array(_numbers(path, header.get("ElementSpacing", "1 1 1"), 3, "ElementSpacing"))
    matrix = header.get("TransformMatrix", header.get("Rotation", header.get("Orientation", "1 0 0 0 1 0 0 0 1")))
    direction = np.array(_numbers(path, matrix, 9, "TransformMatrix")).reshape(3, 3).T  # axis i = triple i
    return origin, spacing, direction, "LPS"


def _nifti_placement(path, reader):
    import numpy as np

    header = reader.GetNIFTIHeader()
    from vtkmodules.vtkCommonDataModel import vtkDataObject

    spacing = np.array(reader.GetOutputInformation(0).Get(vtkDataObject.SPACING()))
    matrix = None
    if header.GetSFormCode() > 0 and reader.GetSFormMatrix() is not None:
        matrix = reader.GetSFormMatrix()
    elif header.GetQFormCode() > 0 and reader.GetQFormMatrix() is not None:
        matrix = reader.GetQFormMatrix()
    if matrix is None:
        return np.zeros(3), spacing, np.eye(3), "RAS"
    m = np.array([[matrix.GetElement(i, j) for j in range(4)] for i in range(4)])
    return m[:3, 3], spacing, m[:3, :3], "RAS"


@functools.lru_cache(maxsize=None)
def _placed_class():
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
    from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData

    class Placed(VTKPythonAlgorithmBase):
        """Passes an image through with the origin, spacing and direction of its file, in the scene's frame."""

        def __init__(self, reader, placement, space):
            VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, inputType="vtkImageData", nOutputPorts=1,
                                            outputType="vtkImageData")
            self.reader, self.placement, self.space = reader, placement, space
            self.SetInputConnection(reader.GetOutputPort())
            self.values = None

        def GetFileName(self):
            return self.reader.GetFileName()

        def RequestInformation(self, request, inInfo, outInfo):
            try:
                origin, spacing, direction, frame = self.placement()
                origin, direction = _to_space(origin, direction, frame, self.space)
            except OracleMeshError as e:
                self.values = None
                self.InvokeEvent("ErrorEvent", str(e))
                return 0
            self.values = (tuple(float(v) for v in origin), tuple(float(v) for v in spacing),
                           tuple(float(v) for v in direction.ravel()))
            info = outInfo.GetInformationObject(0)
            info.Set(vtkDataObject.ORIGIN(), *self.values[0])
            info.Set(vtkDataObject.SPACING(), *self.values[1])
            info.Set(vtkDataObject.DIRECTION(), self.values[2], 9)
            return 1

        def RequestData(self, request, inInfo, outInfo):
            image = vtkImageData.GetData(inInfo[0])
            output = vtkImageData.GetData(outInfo)
            output.ShallowCopy(image)
            output.SetOrigin(*self.values[0])
            output.SetSpacing(*self.values[1])
            output.SetDirectionMatrix(*self.values[2])
            return 1

    return Placed


def _Placed(reader, placement, space):
    return _placed_class()(reader, placement, space)


# ---------------------------------------------------------------------------------------------------
# NRRD (http://teem.sourceforge.net/nrrd/format.html): header fields, then the data.

_NRRD_TYPES = {
    "int8": "i1", "signed char": "i1", "int8_t": "i1", "uchar": "u1", "unsigned char": "u1", "uint8": "u1",
    "uint8_t": "u1", "short": "i2", "short int": "i2", "signed short": "i2", "signed short int": "i2",
    "int16": "i2", "int16_t": "i2", "ushort": "u2", "unsigned short": "u2", "unsigned short int": "u2",
    "uint16": "u2", "uint16_t": "u2", "int": "i4", "signed int": "i4", "int32": "i4", "int32_t": "i4",
    "uint": "u4", "unsigned int": "u4", "uint32": "u4", "uint32_t": "u4", "longlong": "i8", "long long": "i8",
    "long long int": "i8", "signed long long": "i8", "signed long long int": "i8", "int64": "i8",
    "int64_t": "i8", "ulonglong": "u8", "unsigned long long": "u8", "unsigned long long int": "u8",
    "uint64": "u8", "uint64_t": "u8", "float": "f4", "double": "f8",
}
_NRRD_SPACES = {"left-posterior-superior": "LPS", "lps": "LPS", "right-anterior-superior": "RAS", "ras": "RAS"}


def _nrrd_vectors(path, text):
    vectors = []
    for item in text.split():
        if item == "none":
            vectors.append(None)
        else:
            vectors.append(_numbers(path, item.strip("()"), 3, "a space direction"))
    return vectors


def read_nrrd(path):
    """(labels as a numpy array indexed [k, j, i], origin, spacing, direction 3x3, frame or None)."""
    import bz2
    import gzip

    import numpy as np

    with open(path, "rb") as f:
        blob = f.read()
    if not blob.startswith(b"NRRD000"):
        raise OracleMeshError(f"{path}: not a NRRD file (no NRRD000x magic)")
    end = blob.find(b"\n\n")
    header_text = blob[: end if end >= 0 else len(blob)].decode("latin-1")
    fields = {}
    for line in header_text.splitlines()[1:]:
        if line.startswith("#") or ":=" in line:
            continue
        key, sep, value = line.partition(": ")
        if sep:
            fields[key.strip().lower()] = value.strip()
    try:
        dimension = int(fields["dimension"])
        sizes = [int(v) for v in fields["sizes"].split()]
        dtype = np.dtype(_NRRD_TYPES[fields["type"].lower()])
    except (KeyError, ValueError) as e:
        raise OracleMeshError(f"{path}: NRRD header is missing or has a bad 'dimension', 'sizes' or 'type' ({e})") \
            from None
    if dimension != 3 or len(sizes) != 3:
        raise OracleMeshError(f"{path}: a label map must be a 3-D scalar volume, got dimension {dimension}")
    if dtype.itemsize > 1:
        dtype = dtype.newbyteorder(">" if fields.get("endian", "little") == "big" else "<")
    encoding = fields.get("encoding", "raw").lower()
    if "data file" in fields or "datafile" in fields:
        name = fields.get("data file", fields.get("datafile"))
        data_path = name if os.path.isabs(name) else os.path.join(os.path.dirname(path), name)
        try:
            with open(data_path, "rb") as f:
                payload = f.read()
        except OSError:
            raise OracleMeshError(f"{path}: its data file {data_path} cannot be read") from None
    else:
        payload = blob[end + 2:] if end >= 0 else b""
    try:
        if encoding in ("gzip", "gz"):
            payload = gzip.decompress(payload)
        elif encoding in ("bzip2", "bz2"):
            payload = bz2.decompress(payload)
        elif encoding not in ("raw", "ascii", "text", "txt"):
            raise OracleMeshError(f"{path}: NRRD encoding '{encoding}' is not supported (raw, gzip, bzip2, ascii)")
    except (OSError, EOFError, ValueError) as e:
        raise OracleMeshError(f"{path}: the {encoding} data cannot be decompressed ({e})") from None
    count = sizes[0] * sizes[1] * sizes[2]
    check_memory(path, f"sizes {' x '.join(map(str, sizes))}", count, 2 * dtype.itemsize + 6)
    if encoding in ("ascii", "text", "txt"):
        values = np.array(payload.split(), dtype=np.float64)
    else:
        skip = int(fields.get("byte skip", "0"))
        payload = payload[-count * dtype.itemsize:] if skip == -1 else payload[skip:]
        values = np.frombuffer(payload, dtype=dtype, count=min(count, len(payload) // dtype.itemsize))
    if values.size != count:
        raise OracleMeshError(f"{path}: the file is truncated or too long: {values.size} values for sizes "
                              f"{' x '.join(map(str, sizes))} ({count})")
    frame = None
    if "space" in fields:
        frame = _NRRD_SPACES.get(fields["space"].lower())
    if "space directions" in fields:
        vectors = _nrrd_vectors(path, fields["space directions"])
        if len(vectors) != 3 or any(v is None for v in vectors):
            raise OracleMeshError(f"{path}: 'space directions' must give 3 vectors, got {fields['space directions']!r}")
        columns = np.array(vectors).T  # column i: the step along axis i
        spacing = np.linalg.norm(columns, axis=0)
        if (spacing == 0).any():
            raise OracleMeshError(f"{path}: 'space directions' has a zero vector")
        direction = columns / spacing
    else:
        spacing = np.array([float(v) if v.lower() != "nan" else 1.0
                            for v in fields.get("spacings", "1 1 1").split()] or [1.0, 1.0, 1.0])
        direction = np.eye(3)
    origin = np.array(_numbers(path, fields["space origin"].strip("()"), 3, "'space origin'")
                      if "space origin" in fields else [0.0, 0.0, 0.0])
    return values.reshape(sizes[2], sizes[1], sizes[0]), origin, spacing, direction, frame


@functools.lru_cache(maxsize=None)
def _array_reader_class():
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
    from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData
    from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

    class ArrayReader(VTKPythonAlgorithmBase):
        """A label map read by `read` (NRRD, INRIMAGE) as vtkImageData (point scalars 'labels'), placed in
        the scene's frame."""

        def __init__(self, path, space, read):
            VTKPythonAlgorithmBase.__init__(self, nInputPorts=0, nOutputPorts=1, outputType="vtkImageData")
            self.path, self.space, self.read, self.cache = path, space, read, None

        def GetFileName(self):
            return self.path

        def _read(self):
            if self.cache is None:
                labels, origin, spacing, direction, frame = self.read(self.path)
                origin, direction = _to_space(origin, direction, frame, self.space)
                self.cache = (labels, origin, spacing, direction)
            return self.cache

        def RequestInformation(self, request, inInfo, outInfo):
            try:
                labels, origin, spacing, direction = self._read()
            except OracleMeshError as e:
                self.InvokeEvent("ErrorEvent", str(e))
                return 0
            info = outInfo.GetInformationObject(0)
            k, j, i = labels.shape
            info.Set(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT(), (0, i - 1, 0, j - 1, 0, k - 1), 6)
            info.Set(vtkDataObject.ORIGIN(), *origin)
            info.Set(vtkDataObject.SPACING(), *spacing)
            info.Set(vtkDataObject.DIRECTION(), tuple(direction.ravel()), 9)
            return 1

        def RequestData(self, request, inInfo, outInfo):
            labels, origin, spacing, direction = self._read()
            image = vtkImageData.GetData(outInfo)
            k, j, i = labels.shape
            image.SetDimensions(i, j, k)
            image.SetOrigin(*origin)
            image.SetSpacing(*spacing)
            image.SetDirectionMatrix(*direction.ravel())
            array = numpy_to_vtk(labels.ravel().astype(labels.dtype.newbyteorder("=")), deep=True)
            array.SetName("labels")
            image.GetPointData().SetScalars(array)
            return 1

    return ArrayReader


def _ArrayReader(path, space, read):
    return _array_reader_class()(path, space, read)


# ---------------------------------------------------------------------------------------------------
# INRIMAGE-4: a text header padded to a multiple of 256 bytes, ending with "##}\n", then the voxels.

_INR_TYPES = {("unsigned fixed", 8): "u1", ("unsigned fixed", 16): "u2", ("unsigned fixed", 32): "u4",
              ("unsigned fixed", 64): "u8", ("signed fixed", 8): "i1", ("signed fixed", 16): "i2",
              ("signed fixed", 32): "i4", ("signed fixed", 64): "i8", ("float", 32): "f4", ("float", 64): "f8"}


def read_inrimage(path):
    """(labels as a numpy array indexed [k, j, i], origin, spacing, identity direction, no frame)."""
    import gzip

    import numpy as np

    try:
        with (gzip.open(path, "rb") if path.lower().endswith(".gz") else open(path, "rb")) as f:
            blob = f.read()
    except (OSError, EOFError) as e:
        raise OracleMeshError(f"{path}: cannot be read ({e})") from None
    end = blob.find(b"##}\n")
    if not blob.startswith(b"#INRIMAGE-4#{") or end < 0:
        raise OracleMeshError(f"{path}: not an INRIMAGE-4 file (no #INRIMAGE-4#{{ ... ##}} header)")
    header_size = (end + 4 + 255) // 256 * 256
    fields = {}
    for line in blob[:end].decode("latin-1").splitlines()[1:]:
        key, sep, value = line.partition("=")
        if sep:
            fields[key.strip().upper()] = value.strip()
    try:
        sizes = [int(fields[k]) for k in ("XDIM", "YDIM", "ZDIM")]
        components = int(fields.get("VDIM", "1"))
        bits = int(fields.get("PIXSIZE", "8 bits").split()[0])
        dtype = np.dtype(_INR_TYPES[(fields.get("TYPE", "unsigned fixed").lower(), bits)])
    except (KeyError, ValueError) as e:
        raise OracleMeshError(f"{path}: INRIMAGE header has a missing or bad XDIM/YDIM/ZDIM, TYPE or PIXSIZE ({e})") \
            from None
    if components != 1:
        raise OracleMeshError(f"{path}: a label map must have one value per voxel, got VDIM={components}")
    if dtype.itemsize > 1:
        big = fields.get("CPU", "decm").lower() in ("sun", "sgi")
        dtype = dtype.newbyteorder(">" if big else "<")
    count = sizes[0] * sizes[1] * sizes[2]
    check_memory(path, f"XDIM YDIM ZDIM {' x '.join(map(str, sizes))}", count, 2 * dtype.itemsize + 6)
    payload = blob[header_size:]
    if len(payload) < count * dtype.itemsize:
        raise OracleMeshError(f"{path}: the file is truncated: {len(payload)} bytes of data for "
                              f"{' x '.join(map(str, sizes))} voxels of {dtype.itemsize} byte(s)")
    values = np.frombuffer(payload, dtype=dtype, count=count)
    spacing = np.array([float(fields.get(k, "1")) for k in ("VX", "VY", "VZ")])
    origin = np.array([float(fields.get(k, "0")) for k in ("TX", "TY", "TZ")])  # CGAL's Image_3 translation
    return values.reshape(sizes[2], sizes[1], sizes[0]), origin, spacing, np.eye(3), None
