#!/usr/bin/env python3
"""Writes the malformed scenes of tests/data/bad/ (committed; rerun only to change them).

gltf/      glTF and GLB files the loader must refuse with a one-line error
manifest/  scene manifests the manifest parser must refuse (some point at gltf/ files)
Each file's expected message (a substring) is in tests/bad_input_test.cpp; the files also
seed the fuzzers (tools/fuzz.sh).
"""
import base64
import json
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
G = os.path.join(HERE, "gltf")
M = os.path.join(HERE, "manifest")

TRI = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def uri(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def doc(positions=TRI, count=3, indices=None, mode=None, extra_accessor=None, buffer_uri=True):
    """A one-triangle glTF document (edited by the callers)."""
    data = positions + (indices or b"")
    d = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3"}],
        "bufferViews": [{"buffer": 0, "byteLength": len(positions)}],
        "buffers": [{"byteLength": len(data)}],
    }
    if buffer_uri:
        d["buffers"][0]["uri"] = uri(data)
    if indices is not None:
        d["bufferViews"].append({"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices)})
        d["accessors"].append({"bufferView": 1, "componentType": 5125,
                               "count": len(indices) // 4, "type": "SCALAR"})
        d["meshes"][0]["primitives"][0]["indices"] = 1
    if mode is not None:
        d["meshes"][0]["primitives"][0]["mode"] = mode
    return d


def glb(d, binary):
    j = json.dumps(d).encode()
    j += b" " * (-len(j) % 4)
    b = binary + b"\0" * (-len(binary) % 4)
    body = struct.pack("<I", len(j)) + b"JSON" + j + struct.pack("<I", len(b)) + b"BIN\0" + b
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def put(folder, name, content):
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(content if isinstance(content, bytes) else content.encode())


def js(d):
    return json.dumps(d, indent=1)


def main():
    good = doc(buffer_uri=False)
    good_glb = glb(good, TRI)

    # ---- containers ----------------------------------------------------------------------
    put(G, "truncated.glb", good_glb[: len(good_glb) // 2])
    put(G, "truncated_header.glb", good_glb[:7])
    put(G, "wrong_magic.glb", b"glTX" + good_glb[4:])
    put(G, "version1.glb", good_glb[:4] + struct.pack("<I", 1) + good_glb[8:])
    bad_chunk = bytearray(good_glb)
    bad_chunk[12:16] = struct.pack("<I", 0x7FFFFFF0)  # JSON chunk longer than the file
    put(G, "chunk_length.glb", bytes(bad_chunk))
    # The BIN chunk claims 8 bytes more than the file has: tinygltf 2.7 checks its length
    # against the header's total without the chunk's own 8-byte header, and read past the end.
    n = struct.unpack("<I", good_glb[12:16])[0]
    past = bytearray(good_glb)
    past[20 + n:24 + n] = struct.pack("<I", struct.unpack("<I", good_glb[20 + n:24 + n])[0] + 8)
    put(G, "bin_chunk_past_end.glb", bytes(past))
    flipped = bytearray(good_glb)
    flipped[20] = ord("[")  # JSON chunk starts with '[' instead of '{'
    put(G, "corrupted_json_chunk.glb", bytes(flipped))
    put(G, "empty.gltf", b"")
    put(G, "binary_garbage.gltf", bytes(range(256)) * 4)
    put(G, "json_syntax.gltf", js(doc())[:-20])
    put(G, "json_array.gltf", "[1, 2, 3]")

    # ---- references and ranges -----------------------------------------------------------
    d = doc(); d["accessors"][0]["count"] = 4
    put(G, "accessor_past_view.gltf", js(d))
    d = doc(); d["bufferViews"][0]["byteLength"] = 1000
    put(G, "view_past_buffer.gltf", js(d))
    d = doc(); d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7
    put(G, "accessor_missing.gltf", js(d))
    d = doc(); d["accessors"][0]["bufferView"] = 3
    put(G, "buffer_view_missing.gltf", js(d))
    put(G, "index_out_of_range.gltf", js(doc(indices=struct.pack("<3I", 0, 1, 3))))
    d = doc(); d["accessors"][0]["count"] = 4294967295
    put(G, "huge_count.gltf", js(d))
    d = doc(); d["accessors"][0]["byteOffset"] = 18446744073709551000
    put(G, "huge_offset.gltf", js(d))
    d = doc(); d["bufferViews"][0]["byteStride"] = 4
    put(G, "stride_too_small.gltf", js(d))
    d = doc(); d["accessors"][0]["type"] = "VEC2"
    put(G, "position_vec2.gltf", js(d))
    d = doc(); d["accessors"][0]["componentType"] = 5130
    put(G, "component_type_double.gltf", js(d))
    # Sparse accessors are read; this one substitutes more elements than the accessor has.
    d = doc(); d["accessors"][0]["sparse"] = {"count": 4, "indices": {"bufferView": 0, "componentType": 5125},
                                              "values": {"bufferView": 0}}
    put(G, "sparse_count_too_large.gltf", js(d))
    d = doc(); del d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
    put(G, "no_position.gltf", js(d))
    d = doc(); d["nodes"][0]["mesh"] = 5
    put(G, "mesh_missing.gltf", js(d))
    d = doc(); d["meshes"][0]["primitives"][0]["material"] = 2
    put(G, "material_missing.gltf", js(d))

    # ---- external files --------------------------------------------------------------------
    d = doc(); d["buffers"][0]["uri"] = "missing.bin"
    put(G, "missing_buffer.gltf", js(d))
    d = doc(); d["buffers"][0]["uri"] = "."
    put(G, "buffer_is_directory.gltf", js(d))
    d = doc(); d["buffers"][0]["byteLength"] = 1 << 40
    put(G, "buffer_length_mismatch.gltf", js(d))
    d = doc()
    d["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}]
    d["textures"] = [{"source": 0}]
    d["images"] = [{"uri": "missing.png"}]
    d["meshes"][0]["primitives"][0]["material"] = 0
    put(G, "missing_texture.gltf", js(d))
    d["images"] = [{"uri": uri(b"\x89PNG\r\n\x1a\n" + b"\0" * 40)}]
    put(G, "corrupt_texture.gltf", js(d))
    # A PNG header claiming 100000 x 100000 pixels (40 GB decoded), no pixel data.
    ihdr = struct.pack(">IIBBBBB", 100000, 100000, 8, 6, 0, 0, 0)
    import zlib
    png = (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" + ihdr +
           struct.pack(">I", zlib.crc32(b"IHDR" + ihdr)) + struct.pack(">I", 0) + b"IEND" +
           struct.pack(">I", zlib.crc32(b"IEND")))
    d["images"] = [{"uri": uri(png)}]
    put(G, "huge_texture.gltf", js(d))
    # A progressive JPEG (SOF2 after JFIF and quantisation segments) claiming 60000 x 40000
    # pixels (9.6 GB decoded), no scan.
    jfif = b"\xff\xe0" + struct.pack(">H", 16) + b"JFIF\0\x01\x01\0\0\x01\0\x01\0\0"
    dqt = b"\xff\xdb" + struct.pack(">HB", 67, 0) + bytes(range(1, 65))
    sof2 = b"\xff\xc2" + struct.pack(">HBHHB", 17, 8, 40000, 60000, 3) + bytes(
        [1, 0x22, 0, 2, 0x11, 1, 3, 0x11, 1])
    d["images"] = [{"uri": uri(b"\xff\xd8" + jfif + dqt + sof2 + b"\xff\xd9")}]
    put(G, "huge_jpeg_texture.gltf", js(d))

    # ---- primitives and values -------------------------------------------------------------
    put(G, "mode_points.gltf", js(doc(mode=0)))
    put(G, "mode_lines.gltf", js(doc(mode=1)))
    put(G, "mode_invalid.gltf", js(doc(mode=9)))
    put(G, "nan_vertex.gltf", js(doc(positions=struct.pack("<9f", 0, 0, 0, float("nan"), 0, 0, 0, 1, 0))))
    put(G, "inf_vertex.gltf", js(doc(positions=struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, float("inf"), 0))))
    d = doc(); d["nodes"][0]["scale"] = [1e300, 1e300, 1e300]  # vertices overflow float
    put(G, "overflowing_transform.gltf", js(d))
    d = doc(); d["nodes"][0]["matrix"] = [1, 0, 0]
    put(G, "matrix_wrong_length.gltf", js(d))

    d = doc(); d["extensionsUsed"] = d["extensionsRequired"] = ["KHR_texture_basisu"]
    put(G, "required_extension.gltf", js(d))

    # ---- scenes and node graphs ------------------------------------------------------------
    d = doc(); d["scenes"] = []; del d["scene"]
    put(G, "no_scene.gltf", js(d))
    d = doc(); d["scenes"] = [{"nodes": []}]
    put(G, "empty_scene.gltf", js(d))
    d = doc(positions=struct.pack("<9f", 0, 0, 0, 1, 1, 1, 2, 2, 2))
    put(G, "only_degenerate_triangles.gltf", js(d))
    d = doc(); d["scene"] = 3
    put(G, "default_scene_missing.gltf", js(d))
    d = doc(); d["nodes"] = [{"mesh": 0, "children": [1]}, {"children": [0]}]
    put(G, "cyclic_nodes.gltf", js(d))
    d = doc(); d["nodes"] = [{"mesh": 0, "children": [0]}]
    put(G, "self_parent_node.gltf", js(d))
    d = doc(); d["nodes"][0]["children"] = [9]
    put(G, "child_missing.gltf", js(d))
    # JSON nested 100000 deep in "extras" (parsers that recurse run out of stack).
    text = js(doc())
    put(G, "deep_extras.gltf", text[:-1] + ', "extras": ' + "[" * 100000 + "]" * 100000 + "}")
    # A DAG that reuses every node twice: 2^40 instances of one triangle from a tiny file.
    d = doc()
    d["nodes"] = [{"children": [i + 1, i + 1]} for i in range(40)] + [{"mesh": 0}]
    put(G, "exponential_instances.gltf", js(d))

    # ---- manifests -------------------------------------------------------------------------
    put(M, "json_syntax.scene.json", '{"objects": [ {"gltf": "x.glb"} ')
    put(M, "not_an_object.scene.json", "[]")
    put(M, "empty.scene.json", "")
    put(M, "no_objects_key.scene.json", js({"name": "x"}))
    put(M, "empty_objects.scene.json", js({"objects": []}))
    put(M, "missing_mesh.scene.json", js({"objects": [{"gltf": "does_not_exist.glb"}]}))
    put(M, "mesh_is_directory.scene.json", js({"objects": [{"gltf": "."}]}))
    put(M, "bad_mesh.scene.json", js({"objects": [{"gltf": "../gltf/truncated.glb"}]}))
    put(M, "unknown_key.scene.json", js({"objects": [{"quad": {"corner": [0, 0, 0], "u": [1, 0, 0], "v": [0, 1, 0]}}],
                                         "lights": [], "colour": 1}))
    put(M, "wrong_type.scene.json", js({"objects": [{"quad": {"corner": "origin", "u": [1, 0, 0], "v": [0, 1, 0]}}]}))
    put(M, "number_out_of_range.scene.json",
        '{"objects": [{"quad": {"corner": [0, 0, 1e999], "u": [1, 0, 0], "v": [0, 1, 0]}}]}')
    put(M, "self_reference.scene.json", js({"objects": [{"gltf": "self_reference.scene.json"}]}))


if __name__ == "__main__":
    main()
