# stfit export 0.2.0: sample 'ground', ggx, rmse sqrt(L) 0.0418 over 300 points of fits/example.csv, fitted by stfit 0.2.0
# fitted model: ggx alpha 0.3600539896675496, eta 1.51, separable masking, orders single; the fit's scale 0.9682981013553267 is a calibration factor, not applied
# Cycles Glass BSDF: alpha = Roughness^2 (intern/cycles/kernel/svm/closure.h)
# Cycles Principled BSDF, white with Transmission Weight 1 and white Specular Tint: the same GGX glass closure, real dielectric Fresnel (closure.h, bsdf_microfacet.h)
# translation: NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0081 over the sphere of directions, 0.0033 over the measurement grid
# sensitivity: Roughness = 0.600045: rmse grows 8.629e-1 sqrt(L) per unit; change for +10% rmse 4.325e-3
# Principled BSDF (GGX): Roughness 0.6000449897028969, NDF mapped exactly; error from the renderer's masking term; rmse sqrt(L): 0.0081 over the sphere of directions, 0.0033 over the measurement grid
import bpy

def ground_ggx_glass():
    mat = bpy.data.materials.new("ground_ggx_glass")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    glass = nodes.new("ShaderNodeBsdfGlass")
    glass.distribution = 'GGX'
    glass.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    glass.inputs["Roughness"].default_value = 0.6000449897028969
    glass.inputs["IOR"].default_value = 1.51
    out = nodes.get("Material Output")
    mat.node_tree.links.new(glass.outputs["BSDF"], out.inputs["Surface"])
    return mat

def ground_ggx_principled():
    mat = bpy.data.materials.new("ground_ggx_principled")
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes.get("Principled BSDF")
    bsdf.distribution = 'GGX'
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["Metallic"].default_value = 0.0
    bsdf.inputs["Roughness"].default_value = 0.6000449897028969
    bsdf.inputs["IOR"].default_value = 1.51
    bsdf.inputs["Transmission Weight"].default_value = 1.0
    bsdf.inputs["Specular Tint"].default_value = (1.0, 1.0, 1.0, 1.0)
    return mat
