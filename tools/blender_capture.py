"""Renders a Blender scene's cameras into the multilayer EXRs that `import-blender` reads.

    blender -b scene.blend -P tools/blender_capture.py -- OUT [options]
    build/bin/import-blender --out DATASET/train OUT

Runs inside Blender (3.x, its bundled Python; no numpy). It sets Cycles, the passes the
dataset needs (Z, Normal, AO, DiffCol, DiffDir, DiffInd, Emit), the AO distance, a pixel
filter of 0.01 px (data passes are otherwise averaged over Blender's 1.5 px filter), one
sample count for everything (Cycles' AO pass traces one AO ray per sample), then renders
every camera (or those named) into OUT/<camera>.exr, and with --surround the six faces of
a surround frame around a camera into OUT/<camera>-surround/<face>.exr. Each EXR carries
its camera in the header's `Note` (docs/blender.md, "The capture note"), so import-blender
needs no hand-copied numbers. The .blend file itself is not changed.
"""
import argparse
import math
import os
import re
import sys

import bpy
from mathutils import Matrix

# The header note's first line; import-blender (data/blender_capture_note.h) reads the
# key=value lines after it.
NOTE_MAGIC = "nnshade-camera 1"
NOTE_MAX = 700  # Blender keeps at most 767 bytes of stamp_note_text

# docs/dataset-format.md, "Surround (cube) capture": each face is the front camera turned
# in place (Blender's camera space is OpenGL's: -Z forward, +Y up, so the turn is a local
# rotation applied after the camera's own).
FACES = [("front", "Y", 0), ("back", "Y", 180), ("left", "Y", 90), ("right", "Y", -90),
         ("up", "X", 90), ("down", "X", -90)]


class CaptureError(Exception):
    pass


def script_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(
        prog="blender -b scene.blend -P tools/blender_capture.py --",
        description="Render a Blender scene's cameras (Cycles) into multilayer EXRs for "
                    "import-blender, with the camera written into each file's header.",
        epilog="Then: build/bin/import-blender --out DATASET/train OUT (docs/blender.md).")
    p.add_argument("out", metavar="OUT", help="output folder (created)")
    p.add_argument("--camera", action="append", default=[], metavar="NAME",
                   help="render this camera object (repeatable; default: every camera in the scene)")
    p.add_argument("--surround", action="append", default=[], metavar="NAME",
                   help="also render the six 90-degree surround faces around this camera into "
                        "OUT/NAME-surround/<face>.exr (repeatable)")
    p.add_argument("--only-surround", action="store_true",
                   help="render only the --surround faces, no ordinary views")
    p.add_argument("--ao-distance", type=float, metavar="D",
                   help="AO distance in scene units, world.light_settings.distance "
                        "(default: the scene's, Blender's default is 10)")
    p.add_argument("--samples", type=int, default=128,
                   help="Cycles samples per pixel, adaptive sampling off; AO and the indirect "
                        "target both get one ray per sample (default 128)")
    p.add_argument("--filter-size", type=float, default=0.01, metavar="PX",
                   help="pixel filter width; 0.01 keeps depth, normals and AO per pixel (default 0.01)")
    p.add_argument("--resolution", metavar="WxH",
                   help="image size of the views (default: the scene's, with its percentage)")
    p.add_argument("--face-size", type=int, metavar="F",
                   help="size of the square surround faces (default: the views' height)")
    p.add_argument("--frame", type=int, help="frame to render (default: the scene's current frame)")
    p.add_argument("--scene-name", metavar="NAME",
                   help="dataset scene name written into the note (default: the .blend file's name)")
    p.add_argument("--view-layer", metavar="NAME",
                   help="view layer to render (default: the only one enabled for rendering)")
    p.add_argument("--keep-env", action="store_true", help="also enable the Environment pass")
    a = p.parse_args(argv)
    if a.samples < 1:
        p.error("--samples: must be at least 1")
    if not (a.filter_size > 0):
        p.error("--filter-size: must be > 0 (Cycles' minimum is 0.01)")
    if a.ao_distance is not None and not (0 < a.ao_distance < math.inf):
        p.error("--ao-distance: must be a positive number")
    if a.face_size is not None and not 1 <= a.face_size <= 16384:
        p.error("--face-size: must be in [1, 16384]")
    if a.resolution is not None:
        m = re.fullmatch(r"(\d+)x(\d+)", a.resolution)
        if not m or not (1 <= int(m.group(1)) <= 65536 and 1 <= int(m.group(2)) <= 65536):
            p.error("--resolution: expected WxH, e.g. 640x360")
        a.resolution = (int(m.group(1)), int(m.group(2)))
    if a.only_surround and not a.surround:
        p.error("--only-surround: needs --surround NAME")
    if a.scene_name is not None and (not a.scene_name or any(c in a.scene_name for c in "\r\n")):
        p.error("--scene-name: must be a non-empty single line")
    return a


def file_name(name):
    """A camera name as a file name: letters, digits, '.', '_' and '-' only."""
    safe = re.sub(r"[^A-Za-z0-9._-]", "_", name)
    return "_" + safe if safe.startswith(".") or not safe else safe


def rigid(matrix_world):
    """The camera's placement without scale (a scaled camera object renders the same)."""
    loc, rot, _ = matrix_world.decompose()
    return Matrix.Translation(loc) @ rot.to_matrix().to_4x4()


def check_camera(obj):
    cam = obj.data
    if cam.type != "PERSP":
        raise CaptureError(f"camera '{obj.name}' is {cam.type}; the dataset format needs a perspective "
                           "(pinhole) camera")
    if cam.shift_x != 0 or cam.shift_y != 0:
        raise CaptureError(f"camera '{obj.name}' has a lens shift ({cam.shift_x:g}, {cam.shift_y:g}); the "
                           "dataset format puts the principal point at the image centre")


def fov_y_degrees(obj, width, height):
    """Vertical field of view of what Cycles renders at width x height (any sensor fit)."""
    p = obj.calc_matrix_camera(bpy.context.evaluated_depsgraph_get(), x=width, y=height)
    return math.degrees(2 * math.atan(1 / p[1][1]))


def note(fov_y, world_to_camera, ao_radius, scene, camera):
    lines = [NOTE_MAGIC,
             f"fovY={fov_y:.9g}",
             "worldToCamera=" + ",".join(f"{v:.9g}" for row in world_to_camera for v in row),
             f"aoRadius={ao_radius:.9g}",
             f"scene={scene}",
             f"camera={camera}"]
    text = "\n".join(lines)
    if len(text.encode()) > NOTE_MAX:
        raise CaptureError(f"the header note for camera '{camera}' is {len(text.encode())} bytes, Blender keeps "
                           f"{NOTE_MAX}: shorten the scene or camera name (--scene-name)")
    return text


def configure(scene, args):
    """Every render setting the dataset depends on; returns the AO distance in use."""
    r = scene.render
    r.engine = "CYCLES"
    c = scene.cycles
    c.samples = args.samples
    c.use_adaptive_sampling = False  # it stops where Combined looks clean, not AO or DiffInd
    c.use_denoising = False          # touches Combined only; Debian's build has no OIDN
    c.filter_width = args.filter_size
    r.pixel_aspect_x = r.pixel_aspect_y = 1
    r.use_motion_blur = False        # blur would average depth and normals over time
    r.use_multiview = False          # one pinhole view per file, not a stereo pair
    r.use_stamp = False              # no text burnt into the pixels; metadata only
    r.use_stamp_note = True
    r.use_sequencer = False          # write the render, not a sequencer strip
    r.use_file_extension = False
    s = r.image_settings
    s.file_format = "OPEN_EXR_MULTILAYER"
    s.color_depth = "32"
    s.exr_codec = "ZIP"

    layers = [v for v in scene.view_layers if v.use]
    if args.view_layer is not None:
        chosen = scene.view_layers.get(args.view_layer)
        if chosen is None:
            raise CaptureError(f"no view layer '{args.view_layer}'; the scene has: "
                               + ", ".join(v.name for v in scene.view_layers))
    elif len(layers) == 1:
        chosen = layers[0]
    else:
        raise CaptureError("the scene renders " + (f"{len(layers)} view layers ("
                           + ", ".join(v.name for v in layers) + ")" if layers else "no view layer")
                           + "; choose one with --view-layer")
    for v in scene.view_layers:
        v.use = v == chosen
    chosen.use_pass_z = chosen.use_pass_normal = chosen.use_pass_ambient_occlusion = True
    chosen.use_pass_diffuse_color = chosen.use_pass_diffuse_direct = chosen.use_pass_diffuse_indirect = True
    chosen.use_pass_emit = True
    chosen.use_pass_environment = args.keep_env

    if scene.world is None:
        scene.world = bpy.data.worlds.new("nnshade_black")
        scene.world.color = (0, 0, 0)
        print("blender_capture.py: the scene has no world; using a black one (AO needs its distance)")
    ls = scene.world.light_settings
    if args.ao_distance is not None:
        ls.distance = args.ao_distance
    else:
        print(f"blender_capture.py: AO distance {ls.distance:g} (the scene's; set it with --ao-distance)")
    return ls.distance


def render(scene, out_path, note_text):
    """Renders the scene's camera to out_path; the file appears whole or not at all."""
    os.makedirs(os.path.dirname(out_path), exist_ok=True)
    # Blender reads a leading '//' as "next to the .blend": hand it an absolute path.
    partial = os.path.realpath(out_path) + f".partial-{os.getpid()}.exr"
    scene.render.stamp_note_text = note_text
    scene.render.filepath = partial
    try:
        bpy.ops.render.render(write_still=True)
        if not os.path.isfile(partial):
            raise CaptureError(f"Blender wrote no file for {out_path}")
        os.replace(partial, out_path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)
    print(f"blender_capture.py: wrote {out_path}")


def capture(args):
    scene = bpy.context.scene
    cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
    if not cameras:
        raise CaptureError(f"scene '{scene.name}' has no camera object")
    by_name = {o.name: o for o in cameras}
    for name in args.camera + args.surround:
        if name not in by_name:
            raise CaptureError(f"no camera named '{name}'; the scene's cameras: " + ", ".join(by_name))
    views = [] if args.only_surround else [by_name[n] for n in args.camera] or cameras
    surround = [by_name[n] for n in args.surround]
    for obj in views + surround:
        check_camera(obj)
        obj.data.dof.use_dof = False  # the format is a pinhole: depth of field would blur every pass
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise CaptureError(f"{args.out}: exists and is not a folder")
    if "#" in args.out:
        raise CaptureError(f"{args.out}: '#' in the output path (Blender would replace it with the frame number)")

    if args.frame is not None:
        scene.frame_set(args.frame)
    ao = configure(scene, args)
    r = scene.render
    if args.resolution:
        r.resolution_x, r.resolution_y = args.resolution
    else:
        r.resolution_x = max(1, r.resolution_x * r.resolution_percentage // 100)
        r.resolution_y = max(1, r.resolution_y * r.resolution_percentage // 100)
    r.resolution_percentage = 100
    width, height = r.resolution_x, r.resolution_y
    dataset_scene = args.scene_name or (os.path.splitext(os.path.basename(bpy.data.filepath))[0] or scene.name)

    for obj in views:
        scene.camera = obj
        w2c = rigid(obj.matrix_world).inverted()
        text = note(fov_y_degrees(obj, width, height), w2c, ao, dataset_scene, obj.name)
        render(scene, os.path.join(args.out, file_name(obj.name) + ".exr"), text)

    face = args.face_size or height
    for front in surround:
        # One temporary camera turned into each face; the front camera's clipping carries over.
        data = bpy.data.cameras.new("nnshade_face")
        data.type, data.lens_unit, data.sensor_fit = "PERSP", "FOV", "AUTO"
        data.angle = math.pi / 2
        data.clip_start, data.clip_end = front.data.clip_start, front.data.clip_end
        face_cam = bpy.data.objects.new("nnshade_face", data)
        scene.collection.objects.link(face_cam)
        try:
            place = rigid(front.matrix_world)
            # Every face stores its normals in the front camera's space (dataset-format.md).
            text = note(90.0, place.inverted(), ao, dataset_scene, front.name)
            r.resolution_x = r.resolution_y = face
            scene.camera = face_cam
            for name, axis, degrees in FACES:
                face_cam.matrix_world = place @ Matrix.Rotation(math.radians(degrees), 4, axis)
                render(scene, os.path.join(args.out, file_name(front.name) + "-surround", name + ".exr"), text)
        finally:
            bpy.data.objects.remove(face_cam)
            bpy.data.cameras.remove(data)
            r.resolution_x, r.resolution_y = width, height


def main():
    args = script_args()  # argparse exits 2 on bad flags, 0 after --help
    try:
        capture(args)
    except CaptureError as e:
        print(f"blender_capture.py: error: {e}", file=sys.stderr)
        sys.exit(1)
    except Exception as e:  # a Blender error must not end in Blender's exit code 0
        print(f"blender_capture.py: error: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
