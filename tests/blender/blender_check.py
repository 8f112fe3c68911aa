# Runs inside Debian's Blender (blender -b --factory-startup --python blender_check.py -- ...):
# imports the bound mesh with Blender's own OBJ importer, the .mdd with its MDD importer (one
# shape key per frame) and the .pc2 through its Mesh Cache modifier, and prints what Blender
# sees as one JSON line after "RESULT ": vertex counts, frame count, and the positions of some
# vertices at some frames by both routes.
import json
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
obj_path, mdd_path, pc2_path = args[0], args[1], args[2]
frames_to_read = [int(f) for f in args[3].split(",")]
vertices_to_read = [int(v) for v in args[4].split(",")]

bpy.ops.wm.read_factory_settings(use_empty=True)
# Forward Y, up Z: the file's axes as they are (the importer's default turns Y-up into Z-up).
bpy.ops.wm.obj_import(filepath=obj_path, forward_axis="Y", up_axis="Z")
mesh_object = bpy.context.selected_objects[0]
bpy.context.view_layer.objects.active = mesh_object
result = {"obj_vertices": len(mesh_object.data.vertices),
          "obj_first_vertex": list(mesh_object.data.vertices[0].co)}

bpy.ops.preferences.addon_enable(module="io_shape_mdd")
bpy.ops.import_shape.mdd(filepath=mdd_path, frame_start=0, frame_step=1)
keys = mesh_object.data.shape_keys.key_blocks
result["mdd_shape_keys"] = len(keys)
result["mdd"] = {str(f): {str(v): list(keys[f + 1].data[v].co) for v in vertices_to_read} for f in frames_to_read}

# The PC2 on a second copy without shape keys, through the Mesh Cache modifier.
bpy.ops.wm.obj_import(filepath=obj_path, forward_axis="Y", up_axis="Z")
cache_object = bpy.context.selected_objects[0]
modifier = cache_object.modifiers.new("cache", "MESH_CACHE")
modifier.cache_format = "PC2"
modifier.filepath = pc2_path
modifier.forward_axis = "POS_Y"
modifier.up_axis = "POS_Z"
scene = bpy.context.scene
result["pc2"] = {}
for f in frames_to_read:
    scene.frame_set(f)
    evaluated = cache_object.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    result["pc2"][str(f)] = {str(v): list(mesh.vertices[v].co) for v in vertices_to_read}
    evaluated.to_mesh_clear()
print("RESULT " + json.dumps(result))
