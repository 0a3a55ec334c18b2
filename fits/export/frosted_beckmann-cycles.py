# stfit export 0.2.0: sample 'frosted', beckmann, rmse sqrt(L) 0.1130 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: beckmann alpha 0.21829845077431576, eta 1.51, separable masking, orders single; the fit's scale 1.00844442304944 is a calibration factor, not applied
# Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)
# Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0018 over the sphere of directions, 0.0001 over the measurement grid
# sensitivity: Roughness = 0.467224: rmse grows 1.973e0 sqrt(L) per unit; change for +10% rmse 4.109e-4
# Principled BSDF (GGX): Roughness 0.4355641401316906, fitted over the sphere of directions (Nelder-Mead); rmse sqrt(L): 0.1214 over the sphere of directions, 0.1854 over the measurement grid
import bpy

def frosted_beckmann_glass():
    mat = bpy.data.materials.new("frosted_beckmann_glass")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = 'BECKMANN'
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass.inputs["Roughness"].default_value = 0.46722419754793926
    glass.inputs["IOR"].default_value = 1.51
    out = nodes.get("Material Output")
    mat.node_tree.links.new(glass.outputs["BSDF"], out.inputs["Surface"])
    return mat

def frosted_beckmann_principled():
    mat = bpy.data.materials.new("frosted_beckmann_principled")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 0.4355641401316906
    bsdf.inputs["IOR"].default_value = 1.51
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["Specular Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    return mat
