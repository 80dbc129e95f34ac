#!/usr/bin/env python3
"""Writes the fuzzers' seed corpora (committed; rerun only to change them): small VALID inputs
that reach every part of the loaders. The malformed ones come from tests/data/bad/."""
import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def png(w, h):
    rows = b"".join(b"\0" + b"".join(bytes([(x * 60) % 256, (y * 60) % 256, 128, 255])
                                     for x in range(w)) for y in range(h))

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def full_doc():
    """Two-node hierarchy, indexed u16 triangles with normals and uvs, a textured material,
    a camera and a punctual light."""
    pos = struct.pack("<12f", 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0)
    nrm = struct.pack("<12f", *([0, 0, 1] * 4))
    uv = struct.pack("<8f", 0, 0, 1, 0, 1, 1, 0, 1)
    idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0"
    buf = pos + nrm + uv + idx
    img = png(2, 2)
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "spot", "color": [1, 1, 1], "intensity": 5, "spot": {"outerConeAngle": 0.5}}]}},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"children": [1, 2], "translation": [0, 0, -2], "rotation": [0, 0.38268343, 0, 0.9238795],
                   "scale": [2, 2, 2]},
                  {"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5, 0, 0, 1]},
                  {"camera": 0, "translation": [0, 0, 5],
                   "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1, "aspectRatio": 1.5}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
                                    "indices": 3, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [1, 0.5, 0.5, 1], "metallicFactor": 0.5,
                                                "roughnessFactor": 0.3, "baseColorTexture": {"index": 0}},
                       "emissiveFactor": [0.1, 0, 0],
                       "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 2}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(img).decode()}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                        {"buffer": 0, "byteOffset": 96, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
        "buffers": [{"byteLength": len(buf), "uri": uri(buf)}],
    }, buf


def encodings_doc():
    """KHR_mesh_quantization (BYTE positions and normalized SHORT normals in 4-byte padded
    strides, UNSIGNED_SHORT texcoords), a sparse accessor, a strip, a fan, a points primitive,
    KHR_texture_transform and an unknown used extension. (The meshopt and Draco seeds are
    tests/data/gltf_encodings/, which tools/fuzz.sh adds.)"""
    pos = b"".join(struct.pack("<3bx", *p) for p in [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)])
    nrm = b"".join(struct.pack("<3hxx", 0, 0, 32767) for _ in range(4))
    uv = struct.pack("<8H", 0, 0, 65535, 0, 0, 65535, 65535, 65535)
    sparse_idx = struct.pack("<H", 3) + b"\0\0"
    sparse_val = struct.pack("<3bx", 2, 2, 0)
    buf = pos + nrm + uv + sparse_idx + sparse_val
    prims = [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "mode": m, "material": 0}
             for m in (4, 5, 6, 0)]
    prims[0]["attributes"]["POSITION"] = 3
    prims[0]["indices"] = 4
    idx = struct.pack("<6B", 0, 1, 2, 1, 3, 2) + b"\0\0"
    buf += idx
    return {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_mesh_quantization", "KHR_texture_transform", "EXT_unknown"],
        "extensionsRequired": ["KHR_mesh_quantization"],
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "scale": [0.5, 0.5, 0.5]}],
        "meshes": [{"primitives": prims}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {
            "index": 0, "extensions": {"KHR_texture_transform": {
                "offset": [0.5, 0], "rotation": 0.3, "scale": [2, 2]}}}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png(2, 2)).decode()}],
        "accessors": [
            {"bufferView": 0, "componentType": 5120, "count": 4, "type": "VEC3"},
            {"bufferView": 1, "componentType": 5122, "normalized": True, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "normalized": True, "count": 4, "type": "VEC2"},
            {"bufferView": 0, "componentType": 5120, "count": 4, "type": "VEC3",
             "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5123},
                        "values": {"bufferView": 4}}},
            {"bufferView": 5, "componentType": 5121, "count": 6, "type": "SCALAR"}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 16, "byteStride": 4},
                        {"buffer": 0, "byteOffset": 16, "byteLength": 32, "byteStride": 8},
                        {"buffer": 0, "byteOffset": 48, "byteLength": 16},
                        {"buffer": 0, "byteOffset": 64, "byteLength": 2},
                        {"buffer": 0, "byteOffset": 68, "byteLength": 4},
                        {"buffer": 0, "byteOffset": 72, "byteLength": 6}],
        "buffers": [{"byteLength": len(buf), "uri": uri(buf)}],
    }


def glb(d, binary):
    d = json.loads(json.dumps(d))
    d["buffers"] = [{"byteLength": len(binary)}]
    j = json.dumps(d, separators=(",", ":")).encode()
    j += b" " * (-len(j) % 4)
    b = binary + b"\0" * (-len(binary) % 4)
    body = struct.pack("<I", len(j)) + b"JSON" + j + struct.pack("<I", len(b)) + b"BIN\0" + b
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def put(folder, name, content):
    os.makedirs(os.path.join(HERE, folder), exist_ok=True)
    with open(os.path.join(HERE, folder, name), "wb") as f:
        f.write(content if isinstance(content, bytes) else content.encode())


def main():
    d, buf = full_doc()
    put("gltf", "full.gltf", json.dumps(d, separators=(",", ":")))
    put("gltf", "full.glb", glb(d, buf))
    tri = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}],
           "buffers": [{"byteLength": 36, "uri": uri(struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0))}]}
    put("gltf", "triangle.gltf", json.dumps(tri, separators=(",", ":")))
    u8 = json.loads(json.dumps(tri))
    u8["meshes"][0]["primitives"][0]["indices"] = 1
    data = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + bytes([0, 1, 2, 0])
    u8["accessors"].append({"bufferView": 1, "componentType": 5121, "count": 3, "type": "SCALAR"})
    u8["bufferViews"].append({"buffer": 0, "byteOffset": 36, "byteLength": 3})
    u8["buffers"] = [{"byteLength": len(data), "uri": uri(data)}]
    put("gltf", "triangle_u8_indices.gltf", json.dumps(u8, separators=(",", ":")))
    put("gltf", "encodings.gltf", json.dumps(encodings_doc(), separators=(",", ":")))

    # Manifests: tri.glb is written next to the input by fuzz_manifest.cpp.
    put("manifest", "full.scene.json", json.dumps({
        "name": "seed",
        "objects": [
            {"gltf": "tri.glb", "fit": {"base": [0, 0, 0], "size": 2.0},
             "transform": {"translate": [1, 0, 0], "rotate_deg": [0, 90, 0], "scale": [1, 2, 1]},
             "material": {"type": "metal", "color": [0.9, 0.6, 0.5], "roughness": 0.1}},
            {"gltf": "tri.glb", "transform": {"matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 3, 1]},
             "material": {"type": "glass", "ior": 1.3}},
            {"quad": {"corner": [-5, 0, -5], "u": [0, 0, 10], "v": [10, 0, 0]},
             "material": {"type": "emissive", "emission": [1, 1, 1], "strength": 3}},
            {"quad": {"corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0]},
             "material": {"type": "diffuse", "color": [0.5, 0.5, 0.5]}}],
        "lights": [
            {"type": "area", "corner": [-0.5, 3, -0.5], "u": [1, 0, 0], "v": [0, 0, 1], "radiance": [10, 10, 10]},
            {"type": "point", "position": [2, 3, 2], "intensity": [20, 20, 20]},
            {"type": "environment", "radiance": [0.1, 0.1, 0.1]}],
        "camera": {"position": [0, 0.6, 3], "target": [0, 0.4, 0], "up": [0, 1, 0], "yfov_deg": 40}},
        indent=1))
    put("manifest", "quad.scene.json",
        '{"objects": [{"quad": {"corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0]}}]}')
    put("manifest", "gltf_only.scene.json", '{"objects": [{"gltf": "tri.glb"}]}')
    pbrt_seeds()
    mesh_seeds()


TRI = 'Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]\n'


def pbrt_seeds():
    """pbrt-v4 files: every directive family, shape and light kind the reader takes."""
    put("pbrt", "camera.pbrt",
        'LookAt 0 1 5  0 0 0  0 1 0\nCamera "perspective" "float fov" [ 45 ]\n'
        'Film "rgb" "integer xresolution" [ 64 ] "integer yresolution" [ 48 ]\n'
        'Sampler "halton" "integer pixelsamples" 4\nWorldBegin\n'
        'LightSource "infinite" "rgb L" [ 0.2 0.2 0.2 ]\n'
        'AttributeBegin\n  AreaLightSource "diffuse" "rgb L" [ 5 5 5 ] "bool twosided" false\n'
        '  Translate 0 3 0\n  ReverseOrientation\n  Shape "disk" "float radius" 1\nAttributeEnd\n'
        'Material "coateddiffuse" "rgb reflectance" [ 0.4 0.2 0.2 ] "float roughness" 0.1\n'
        'Shape "sphere" "float radius" 0.5 "float zmin" -0.2 "float phimax" 270\n' + TRI)
    put("pbrt", "transforms.pbrt",
        'WorldBegin\nAttributeBegin\n Translate 1 2 3 Scale 2 2 2 Rotate 30 0 1 0\n' + TRI +
        'AttributeEnd\nTransform [ 1 0 0 0 0 1 0 0 0 0 1 0 5 6 7 1 ]\nConcatTransform [ 2 0 0 0 0 2 0 0 '
        '0 0 2 0 0 0 0 1 ]\nCoordinateSystem "here"\nIdentity\nCoordSysTransform "here"\n' + TRI +
        'Include "inc.pbrt"\nImport "inc.pbrt"\n')
    put("pbrt", "instances.pbrt",
        'WorldBegin\nObjectBegin "o"\n Translate 1 0 0\n' + TRI +
        ' Shape "bilinearmesh" "point3 P" [ 0 0 0 1 0 0 0 1 0 1 1 0 ]\nObjectEnd\n'
        'ObjectInstance "o"\nScale -1 1 1\nObjectInstance "o"\n')
    put("pbrt", "materials.pbrt",
        'WorldBegin\nLightSource "point" "point3 from" [ 0 4 0 ] "rgb I" [ 3 3 3 ] "float power" 10\n'
        'LightSource "spot" "point3 from" [ 0 4 0 ] "point3 to" [ 0 0 0 ] "float coneangle" 25\n'
        'LightSource "distant" "point3 to" [ 0 -1 0 ] "blackbody L" [ 5500 ]\n'
        'MakeNamedMaterial "gold" "string type" "conductor" "spectrum eta" "metal-Au-eta" '
        '"spectrum k" "metal-Au-k" "float roughness" 0.01\nNamedMaterial "gold"\n' + TRI +
        'Material "dielectric" "spectrum eta" "glass-BK7"\n' + TRI +
        'Texture "c" "spectrum" "constant" "rgb value" [ 0.3 0.6 0.9 ]\n'
        'Texture "s" "spectrum" "scale" "texture tex" "c" "float scale" 0.5\n'
        'Material "diffuse" "texture reflectance" "s"\n'
        'Shape "plymesh" "string filename" "tri.ply"\n'
        'Shape "loopsubdiv" "integer levels" 2 "point3 P" [ 0 0 0 1 0 0 0 1 0 0 0 1 ] '
        '"integer indices" [ 0 2 1 0 1 3 0 3 2 1 2 3 ]\n')


def ply(fmt, body):
    head = ("ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
            "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
            "property float s\nproperty float t\nelement face 2\n"
            "property list uchar int vertex_indices\nend_header\n" % fmt).encode()
    return head + body


def mesh_seeds():
    """OBJ and PLY (the first byte picks: odd .obj, even .ply): faces of every form, MTL, and
    PLY in each encoding."""
    obj = ("mtllib m.mtl\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
           "vn 0 0 1\nusemtl a\nf 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf -4/-3/-1 -3/-2/-1 -2/-1/-1\n"
           "g b\nusemtl g\nf 1 2 3 4\n")
    put("mesh", "faces.obj", b"\x01" + obj.encode())
    verts = [(0, 0, 0, 0, 0, 1, 0, 0), (1, 0, 0, 0, 0, 1, 1, 0), (1, 1, 0, 0, 0, 1, 1, 1),
             (0, 1, 0, 0, 0, 1, 0, 1)]
    faces = [(0, 1, 2), (0, 1, 2, 3)]
    text = "".join(" ".join(str(x) for x in v) + "\n" for v in verts)
    text += "".join(f"{len(f)} " + " ".join(map(str, f)) + "\n" for f in faces)
    put("mesh", "ascii.ply", b"\x00" + ply("ascii", text.encode()))
    for name, e in (("le.ply", "<"), ("be.ply", ">")):
        body = b"".join(struct.pack(e + "8f", *v) for v in verts)
        body += b"".join(struct.pack(e + "B", len(f)) + struct.pack(e + "%di" % len(f), *f)
                         for f in faces)
        fmt = "binary_little_endian" if e == "<" else "binary_big_endian"
        put("mesh", name, b"\x00" + ply(fmt, body))


if __name__ == "__main__":
    main()
