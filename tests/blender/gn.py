"""Shared by the reference scripts: evaluates a geometry-nodes tree at the vertices of a
point mesh and reads the attributes it stored (Blender's Python module, bpy 4.2.0)."""
import bpy


def point_object(points):
    """A mesh object whose vertices are `points`, linked into the scene."""
    mesh = bpy.data.meshes.new("pts")
    mesh.from_pydata(points, [], [])
    obj = bpy.data.objects.new("pts", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def evaluate(obj, make, outputs):
    """Builds position → the node `make(tree, position)` makes → one stored attribute per
    (socket name, data type) of `outputs`, and returns {name: values} (vectors as lists).
    Attributes are stored as `out_NAME`, which no built-in attribute (such as `radius`) is."""
    tree = bpy.data.node_groups.new("t", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    gin = tree.nodes.new("NodeGroupInput")
    gout = tree.nodes.new("NodeGroupOutput")
    pos = tree.nodes.new("GeometryNodeInputPosition")
    node = make(tree, pos)
    sockets = {s.name: s for s in node.outputs}
    geo = gin.outputs[0]
    for name, kind in outputs:
        st = tree.nodes.new("GeometryNodeStoreNamedAttribute")
        st.data_type = kind
        st.inputs["Name"].default_value = "out_" + name
        tree.links.new(geo, st.inputs["Geometry"])
        tree.links.new(sockets[name], st.inputs["Value"])
        geo = st.outputs[0]
    tree.links.new(geo, gout.inputs[0])
    for m in list(obj.modifiers):
        obj.modifiers.remove(m)
    obj.modifiers.new("gn", "NODES").node_group = tree
    dg = bpy.context.evaluated_depsgraph_get()
    dg.update()
    ev = obj.evaluated_get(dg).data
    result = {}
    for name, kind in outputs:
        data = ev.attributes["out_" + name].data
        result[name] = [a.value for a in data] if kind == "FLOAT" else [list(a.vector) for a in data]
    return result


def link_coordinates(tree, pos, node, dims):
    """Links the position into `node`'s Vector, or for 1D its x into W; returns the node's
    input sockets by name."""
    sock = {s.name: s for s in node.inputs}
    if dims == "1D":
        sep = tree.nodes.new("ShaderNodeSeparateXYZ")
        tree.links.new(pos.outputs[0], sep.inputs[0])
        tree.links.new(sep.outputs[0], sock["W"])
    else:
        tree.links.new(pos.outputs[0], sock["Vector"])
    return sock
