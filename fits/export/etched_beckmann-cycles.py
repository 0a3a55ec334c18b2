# stfit export 0.2.0: sample 'etched', beckmann, rmse sqrt(L) 0.1207 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.5193579495293195, eta 1.51, separable masking, orders single; the fit's scale 1.0119956915431843 is a calibration factor, not applied
# Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)
# Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0035 over the sphere of directions, 0.0007 over the measurement grid
# sensitivity: Roughness = 0.720665: rmse grows 9.626e-1 sqrt(L) per unit; change for +10% rmse 1.676e-3
# Principled BSDF (GGX): Roughness 0.6630088650707717, fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.1017 over the sphere of directions, 0.1694 over the measurement grid
import bpy

def etched_beckmann_glass():
    mat = bpy.data.materials.new("etched_beckmann_glass")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = 'BECKMANN'
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass.inputs["Roughness"].default_value = 0.7206649356873965
    glass.inputs["IOR"].default_value = 1.51
    out = nodes.get("Material Output")
    mat.node_tree.links.new(glass.outputs["BSDF"], out.inputs["Surface"])
    return mat

def etched_beckmann_principled():
    mat = bpy.data.materials.new("etched_beckmann_principled")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 0.6630088650707717
    bsdf.inputs["IOR"].default_value = 1.51
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["Specular Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    return mat
