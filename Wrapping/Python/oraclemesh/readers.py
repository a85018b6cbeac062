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


def _check_exists(path):
    if not os.path.isfile(path):
        raise OracleMeshError(f"{path}: file not found")


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
    if encoding in ("ascii", "text", "txt"):
        values = np.array(payload.split(), dtype=np.float64)
    else:
        skip = int(fields.get("byte skip", "0"))
        payload = payload[-count * dtype.itemsize:] if skip == -1 else payload[skip:]
        values = np.frombuffer(payload, dtype=dtype, count=min(count, len(payload) // dtype.itemsize))
    if values.size != count:
        raise OracleMeshError(f"{path}: {values.size} values for sizes {' x '.join(map(str, sizes))} ({count})")
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
    payload = blob[header_size:]
    if len(payload) < count * dtype.itemsize:
        raise OracleMeshError(f"{path}: {len(payload)} bytes of data for {' x '.join(map(str, sizes))} voxels "
                              f"of {dtype.itemsize} byte(s)")
    values = np.frombuffer(payload, dtype=dtype, count=count)
    spacing = np.array([float(fields.get(k, "1")) for k in ("VX", "VY", "VZ")])
    origin = np.array([float(fields.get(k, "0")) for k in ("TX", "TY", "TZ")])  # CGAL's Image_3 translation
    return values.reshape(sizes[2], sizes[1], sizes[0]), origin, spacing, np.eye(3), None
