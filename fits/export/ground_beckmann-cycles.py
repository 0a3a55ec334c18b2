# stfit export 0.2.0: sample 'ground', beckmann, rmse sqrt(L) 0.1932 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.4017264750073634, eta 1.51, separable masking, orders single; the fit's scale 0.8663756013723194 is a calibration factor, not applied
# Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)
# Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0027 over the sphere of directions, 0.0004 over the measurement grid
# sensitivity: Roughness = 0.633819: rmse grows 1.111e0 sqrt(L) per unit; change for +10% rmse 1.098e-3
# Principled BSDF (GGX): Roughness 0.5861362058253732, fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.0978 over the sphere of directions, 0.1597 over the measurement grid
import bpy

def ground_beckmann_glass():
    mat = bpy.data.materials.new("ground_beckmann_glass")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = 'BECKMANN'
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass.inputs["Roughness"].default_value = 0.6338189607509098
    glass.inputs["IOR"].default_value = 1.51
    out = nodes.get("Material Output")
    mat.node_tree.links.new(glass.outputs["BSDF"], out.inputs["Surface"])
    return mat

def ground_beckmann_principled():
    mat = bpy.data.materials.new("ground_beckmann_principled")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 0.5861362058253732
    bsdf.inputs["IOR"].default_value = 1.51
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["Specular Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    return mat
