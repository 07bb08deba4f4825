#!/usr/bin/env python3
"""How much of a corpus of pbrt-v4 scenes steradian parses and builds.

Usage: scripts/pbrt_corpus.py CORPUS_DIR [--steradian build/release/steradian]
                               [--markdown] [--json FILE] [--no-standins] [--timeout S]

CORPUS_DIR is a copy of a scene collection such as github.com/mmp/pbrt-v4-scenes (not
part of this repository: it is third-party content). The script

1. finds the top-level scenes: the .pbrt files that contain WorldBegin (a file Included by a
   scene holds geometry, materials or lights and no WorldBegin);
2. follows their Include/Import directives and collects every file they name ("string
   filename", spectrum files, Include), and creates a small stand-in of the same format for
   each binary asset that is absent: a PLY mesh (plain or .ply.gz) of one quad with
   positions, normals and uv; an image texture or environment map as an 8x8 RGB image (EXR
   uncompressed float scanlines, PNG, TGA or PFM; square, so it is also a valid
   equal-area map); a spectrum file (.spd) of two samples; a NanoVDB grid file (.nvdb) of a
   ball of density in 16^3 voxels with, when its MakeNamedMedium has "temperature..."
   parameters, a "temperature" grid (written by steradian_nvdb_standin, built beside the
   steradian binary, with NanoVDB's own API). A stand-in is never written over a
   file that exists, and every one is listed in CORPUS_DIR/.standins.txt. Scene text that is
   absent (.pbrt, .pbrt.gz) and assets of other formats (.bsdf, .jpg, ...) are left
   missing: the scene is then reported as blocked by that file;
3. runs `steradian check --json` on each top-level scene (one process each);
4. prints a table: each scene, ok or what blocks it; the count "N of M parse and build";
   and, for each blocking feature, the number of scenes it blocks.

Only the Python standard library is used (and steradian_nvdb_standin for .nvdb files).
"""
import argparse
import collections
import gzip
import json
import os
import re
import struct
import subprocess
import sys
import tempfile
import zlib

# ---- reading scene text -------------------------------------------------------------------

TOKEN = re.compile(r'"[^"\n]*"|\[|\]|#[^\n]*|[^\s"\[\]#]+')


def tokens(text):
    """The tokens of pbrt scene text, comments dropped (strings keep their quotes)."""
    for m in TOKEN.finditer(text):
        t = m.group(0)
        if not t.startswith("#"):
            yield t


def read_scene_text(path):
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".gz"):
        data = gzip.decompress(data)
    return data.decode("utf-8", errors="replace")


def is_top_level(path):
    """A scene file: it has WorldBegin (outside comments and strings)."""
    try:
        return any(t == "WorldBegin" for t in tokens(read_scene_text(path)))
    except OSError:
        return False


FILE_PARAM = re.compile(r'^"(string|spectrum)\s+(\w+)"$')

# The .nvdb files named by a MakeNamedMedium with "temperature..." parameters (their stand-in
# gets a "temperature" grid too); filled by referenced_files().
NVDB_WITH_TEMPERATURE = set()


def is_directive(t):
    return t[0].isalpha() and t[0].isupper()


def statement_params(toks, i):
    """The parameter declarations ("type name") of the directive statement around token i."""
    start = i
    while start > 0 and not is_directive(toks[start]):
        start -= 1
    end = i + 1
    while end < len(toks) and not is_directive(toks[end]):
        end += 1
    return [t for t in toks[start:end] if t.startswith('"') and " " in t.strip('"').strip()]


def referenced_files(path, base_dir, seen):
    """(referenced path, kind) for every file the scene text at `path` names, following
    Include and Import (names resolve against `base_dir`, the top-level scene's directory,
    as in pbrt-v4)."""
    if path in seen:
        return
    seen.add(path)
    if not os.path.isfile(path):
        return
    toks = list(tokens(read_scene_text(path)))
    directive = ""
    for i, t in enumerate(toks):
        if t[0].isalpha() and t[0].isupper():
            directive = t
        if t in ("Include", "Import") and i + 1 < len(toks) and toks[i + 1].startswith('"'):
            inc = os.path.join(base_dir, toks[i + 1].strip('"'))
            yield inc, "scene"
            yield from referenced_files(inc, base_dir, seen)
            continue
        m = FILE_PARAM.match(t)
        if not m:
            continue
        ptype, pname = m.groups()
        j = i + 1
        if j < len(toks) and toks[j] == "[":
            j += 1
        if j >= len(toks) or not toks[j].startswith('"'):
            continue
        value = toks[j].strip('"')
        if directive == "Film":  # its filename is an output
            continue
        if ptype == "string" and pname in ("filename", "lensfile", "mapname", "bsdffile"):
            if directive == "MakeNamedMedium" and value.lower().endswith(".nvdb") and any(
                    "temperature" in p for p in statement_params(toks, i)):
                NVDB_WITH_TEMPERATURE.add(os.path.join(base_dir, value))
            yield os.path.join(base_dir, value), "asset"
        elif ptype == "spectrum" and "." in value:  # a named spectrum has no extension
            yield os.path.join(base_dir, value), "asset"


# ---- stand-ins ----------------------------------------------------------------------------

def ply_bytes(verts, normal, faces):
    """An ASCII PLY mesh: vertices (x, y, z, u, v) sharing one normal, faces of 3 or 4
    vertex indices."""
    lines = ["ply", "format ascii 1.0", "comment written by scripts/pbrt_corpus.py",
             f"element vertex {len(verts)}", "property float x", "property float y",
             "property float z", "property float nx", "property float ny", "property float nz",
             "property float u", "property float v", f"element face {len(faces)}",
             "property list uchar int vertex_indices", "end_header"]
    nx, ny, nz = normal
    lines += [f"{x} {y} {z} {nx} {ny} {nz} {u} {v}" for x, y, z, u, v in verts]
    lines += [" ".join(str(i) for i in [len(f), *f]) for f in faces]
    return ("\n".join(lines) + "\n").encode()


def ply_standin():
    """A PLY mesh of one unit quad (two triangles) with positions, normals and uv."""
    verts = [(0, 0, 0, 0, 0), (1, 0, 0, 1, 0), (1, 1, 0, 1, 1), (0, 1, 0, 0, 1)]
    return ply_bytes(verts, (0, 0, 1), [(0, 1, 2), (0, 2, 3)])


N = 8  # stand-in images are N x N


def pixels():
    """An N x N RGB image in [0.2, 0.8]: smooth, so every texture lookup is finite."""
    return [[(0.2 + 0.6 * x / (N - 1), 0.2 + 0.6 * y / (N - 1), 0.5) for x in range(N)]
            for y in range(N)]


def exr_bytes(img):
    """An OpenEXR file of img (rows from the top, each a list of (r, g, b) floats):
    uncompressed scanlines, 32-bit float channels B, G, R."""
    h, w = len(img), len(img[0])

    def attr(name, type_, data):
        return name.encode() + b"\0" + type_.encode() + b"\0" + struct.pack("<i", len(data)) + data

    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iB3xii", 2, 0, 1, 1) for c in "BGR") + b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    header = (struct.pack("<ii", 20000630, 2) + attr("channels", "chlist", chlist)
              + attr("compression", "compression", b"\0") + attr("dataWindow", "box2i", box)
              + attr("displayWindow", "box2i", box) + attr("lineOrder", "lineOrder", b"\0")
              + attr("pixelAspectRatio", "float", struct.pack("<f", 1))
              + attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
              + attr("screenWindowWidth", "float", struct.pack("<f", 1)) + b"\0")
    blocks = []
    for y in range(h):
        data = b"".join(struct.pack(f"<{w}f", *[img[y][x][c] for x in range(w)]) for c in (2, 1, 0))
        blocks.append(struct.pack("<ii", y, len(data)) + data)
    offset = len(header) + 8 * h
    table = b""
    for b in blocks:
        table += struct.pack("<Q", offset)
        offset += len(b)
    return header + table + b"".join(blocks)


def png_bytes(img):
    """An 8-bit RGB PNG of img (rows from the top, each a list of (r, g, b) bytes 0-255)."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    h, w = len(img), len(img[0])
    raw = b"".join(b"\0" + bytes(v for px in row for v in px) for row in img)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def exr_standin():
    return exr_bytes(pixels())


def png_standin():
    return png_bytes([[tuple(int(255 * v) for v in px) for px in row] for row in pixels()])


def tga_standin():
    header = struct.pack("<BBBHHBHHHHBB", 0, 0, 2, 0, 0, 0, 0, 0, N, N, 24, 0)
    return header + b"".join(bytes(int(255 * v) for v in reversed(px)) for row in reversed(pixels()) for px in row)


def pfm_standin():
    rows = reversed(pixels())  # PFM stores the bottom row first
    return f"PF\n{N} {N}\n-1.0\n".encode() + b"".join(struct.pack(f"<{3 * N}f", *[v for px in row for v in px]) for row in rows)


def spd_standin():
    return b"# stand-in written by scripts/pbrt_corpus.py\n400 0.5\n700 0.5\n"


# The program that writes stand-in .nvdb files (tests/tools/nvdb_standin.cpp); set by main().
NVDB_STANDIN = None


def nvdb_standin(path):
    if not NVDB_STANDIN or not os.access(NVDB_STANDIN, os.X_OK):
        return None
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "standin.nvdb")
        args = [NVDB_STANDIN, out] + (["--temperature"] if path in NVDB_WITH_TEMPERATURE else [])
        if subprocess.run(args).returncode != 0:
            return None
        with open(out, "rb") as f:
            return f.read()


STANDINS = {".ply": ply_standin, ".exr": exr_standin, ".png": png_standin,
            ".tga": tga_standin, ".pfm": pfm_standin, ".spd": spd_standin}


def standin_for(path):
    """The bytes of a stand-in for the asset at `path`, or None for a format we do not make."""
    if path.lower().endswith(".nvdb"):
        return nvdb_standin(path)
    p = path.lower()
    gz = p.endswith(".gz")
    if gz:
        p = p[:-3]
    make = STANDINS.get(os.path.splitext(p)[1])
    if make is None or (gz and not p.endswith(".ply")):
        return None
    data = make()
    return gzip.compress(data) if gz else data


# ---- classifying what blocks a scene ------------------------------------------------------

RULES = [
    (re.compile(r'^(.*?)"([^"]+)" is not supported yet'), lambda m: f'{m.group(1)}"{m.group(2)}"'),
    (re.compile(r'^unused parameter "([^"]+)" for (Shape|Material|LightSource|Texture|Camera|Film|'
                r'Sampler|Integrator|PixelFilter|AreaLightSource) ?("[^"]*")?'),
     lambda m: f'parameter "{m.group(1)}" of {m.group(2)} {m.group(3) or ""}'.strip()),
    (re.compile(r'^unused parameter "([^"]+)" for material'),
     lambda m: f'parameter "{m.group(1)}" of a named material'),
    (re.compile(r'^unused parameter "([^"]+)" for (\S+)'),
     lambda m: f'parameter "{m.group(1)}" of {m.group(2)}'),
    (re.compile(r'^[^:]*: (.*?) are not supported yet'), lambda m: m.group(1)),
    (re.compile(r'^(.*?) is not supported yet'), lambda m: m.group(1)),
    (re.compile(r'^(?:Include|Import): cannot find file "([^"]+)"'), lambda m: missing_key(m.group(1))),
    (re.compile(r'^cannot read .*"([^"]+)"'), lambda m: missing_key(m.group(1))),
]


NOT_FETCHED = "scene text not in the corpus copy (Include of a file not fetched)"


def missing_key(path):
    ext = path.lower()
    ext = (os.path.splitext(ext[:-3])[1] + ".gz") if ext.endswith(".gz") else os.path.splitext(ext)[1]
    if ext in (".pbrt", ".pbrt.gz"):
        return NOT_FETCHED
    return f"missing asset of a format without stand-in ({ext or 'no extension'})"


def feature_of(message):
    for rx, key in RULES:
        m = rx.search(message)
        if m:
            return key(m)
    # Otherwise the message itself, without parenthesised details (locations) and with its
    # numbers generalised.
    key = re.sub(r"\s*\([^)]*\)", "", message)
    return re.sub(r'(?<![\w"])-?\d+(\.\d+)?', "N", key)[:100]


# Warnings after which a scene builds but its image is not pbrt-v4's (what is ignored).
IMAGE_WARNINGS = [
    (re.compile(r"participating media are not supported"), "participating media ignored"),
    (re.compile(r"motion blur is not supported"), "motion blur ignored"),
]


def ignored_features(warnings):
    return sorted({key for w in warnings for rx, key in IMAGE_WARNINGS if rx.search(w["message"])})


# ---- main ---------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("corpus")
    ap.add_argument("--steradian", default=os.path.join(os.path.dirname(__file__), "..", "build",
                                                        "release", "steradian"))
    ap.add_argument("--markdown", action="store_true", help="tables in Markdown")
    ap.add_argument("--json", help="write every scene's check results to this file")
    ap.add_argument("--no-standins", action="store_true", help="do not create stand-in assets")
    ap.add_argument("--timeout", type=float, default=900, help="seconds per scene")
    ap.add_argument("--nvdb-standin", help="the program writing stand-in .nvdb files (default: "
                    "steradian_nvdb_standin beside the steradian binary)")
    a = ap.parse_args()
    corpus = os.path.abspath(a.corpus)
    global NVDB_STANDIN
    NVDB_STANDIN = a.nvdb_standin or os.path.join(os.path.dirname(os.path.abspath(a.steradian)),
                                                  "steradian_nvdb_standin")

    scenes = []
    for root, dirs, files in os.walk(corpus):
        dirs.sort()
        for f in sorted(files):
            if f.endswith(".pbrt") and is_top_level(os.path.join(root, f)):
                scenes.append(os.path.join(root, f))
    if not scenes:
        sys.exit(f"pbrt_corpus: no top-level .pbrt scene (a file with WorldBegin) under {corpus}")

    manifest = os.path.join(corpus, ".standins.txt")
    standins = set(open(manifest).read().split("\n")) - {""} if os.path.exists(manifest) else set()
    made = 0
    for s in scenes:
        for path, kind in referenced_files(s, os.path.dirname(s), set()):
            if kind != "asset" or os.path.exists(path) or a.no_standins:
                continue
            data = standin_for(path)
            if data is None:
                continue
            os.makedirs(os.path.dirname(path), exist_ok=True)
            with open(path, "wb") as f:
                f.write(data)
            standins.add(os.path.relpath(path, corpus))
            made += 1
    with open(manifest, "w") as f:
        f.write("".join(p + "\n" for p in sorted(standins)))

    results = []
    blocking = collections.Counter()
    ignored = collections.Counter()  # over the scenes that build
    with tempfile.TemporaryDirectory() as tmp:
        for s in scenes:
            out = os.path.join(tmp, "check.json")
            try:
                subprocess.run([a.steradian, "check", "--quiet", "--json", out, s],
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, timeout=a.timeout)
                with open(out) as f:
                    r = json.load(f)["results"][0]
            except subprocess.TimeoutExpired:
                r = {"scene": s, "ok": False, "errors": [
                    {"message": f"check took longer than {a.timeout:g} s", "unsupported": False}]}
            except (OSError, ValueError, KeyError, IndexError) as e:
                r = {"scene": s, "ok": False, "errors": [
                    {"message": f"steradian check failed: {e}", "unsupported": False}]}
            if os.path.exists(out):
                os.remove(out)
            r["scene"] = os.path.relpath(s, corpus)
            r["blocking"] = sorted({feature_of(e["message"]) for e in r["errors"]})
            r["ignored"] = ignored_features(r.get("warnings", []))
            blocking.update(r["blocking"])
            if r["ok"]:
                ignored.update(r["ignored"])
            results.append(r)

    ok = sum(1 for r in results if r["ok"])
    md = a.markdown
    print("| scene | result |\n|---|---|" if md else f"{'scene':50s} result")
    for r in results:
        what = "; ".join(r["blocking"])
        if r["ok"]:
            what = "ok" + (f" (built, but {', '.join(r['ignored'])})" if r["ignored"] else "")
        print(f"| {r['scene']} | {what} |" if md else f"{r['scene']:50s} {what}")
    print()
    exact = sum(1 for r in results if r["ok"] and not r["ignored"])
    unfetched = sum(1 for r in results if r["blocking"] == [NOT_FETCHED])
    print(f"{ok} of {len(results)} top-level scenes parse and build; {exact} of them without "
          f"ignoring a feature that changes the image")
    print(f"{unfetched} scenes are blocked only by scene text missing from the corpus copy; "
          f"{made} stand-in assets made now, {len(standins)} listed in {manifest}")
    print()
    print("| scenes blocked | feature |\n|---|---|" if md else "scenes blocked  feature")
    for feat, n in sorted(blocking.items(), key=lambda kv: (-kv[1], kv[0])):
        print(f"| {n} | {feat} |" if md else f"{n:14d}  {feat}")
    if ignored:
        print()
        print("| scenes that build with | ignored |\n|---|---|" if md else "scenes that build with  ignored")
        for feat, n in sorted(ignored.items(), key=lambda kv: (-kv[1], kv[0])):
            print(f"| {n} | {feat} |" if md else f"{n:22d}  {feat}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"scenes_ok": ok, "scenes_ok_exact": exact, "scenes": len(results),
                       "results": results}, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
