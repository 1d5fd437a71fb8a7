"""A small Blender room for test_blender_capture (tests/apps): a floor, a back wall facing
the first camera, a left wall, a box and a sphere, no ceiling (the sky shows above the
walls), a sun and a grey-blue sky; two cameras. Built from primitives, nothing imported.

    blender -b --factory-startup --python tests/apps/blender_room.py -- OUT.blend
"""
import math
import sys

import bpy

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def box(name, location, half_size):
    bpy.ops.mesh.primitive_cube_add(location=location)
    o = bpy.context.active_object
    o.name, o.scale = name, half_size


# Floor top at z = 0; the back wall's front face at y = 2.95; the left wall's at x = -2.95.
# The back wall's top (z = 1.95) is seen by "Front" at 48x32 0.3 px above the centre of
# pixel row 3: a 1.5 px pixel filter would mix the sky into that row, 0.01 px does not.
box("floor", (0, 0, -0.05), (4, 4, 0.05))
box("back_wall", (0, 3, 0.975), (3, 0.05, 0.975))
box("left_wall", (-3, 0, 1), (0.05, 3, 1))
box("block", (1.5, 1, 0.4), (0.4, 0.4, 0.4))
bpy.ops.mesh.primitive_uv_sphere_add(location=(-1.5, 1.5, 0.5), radius=0.5)
bpy.ops.object.light_add(type="SUN", location=(0, 0, 5), rotation=(0.5, 0.3, 0))

# "Front": at eye height 1, level, looking along +y at the back wall.
bpy.ops.object.camera_add(location=(0, -2, 1), rotation=(math.radians(90), 0, 0))
bpy.context.active_object.name = "Front"
scene.camera = bpy.context.active_object
# "Corner": higher, turned 30 degrees to the left and tilted down.
bpy.ops.object.camera_add(location=(2, -2, 1.5), rotation=(math.radians(80), 0, math.radians(30)))
bpy.context.active_object.name = "Corner"

world = bpy.data.worlds.new("sky")
world.color = (0.5, 0.6, 0.8)
scene.world = world
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[sys.argv.index("--") + 1])
