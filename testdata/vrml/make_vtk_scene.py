"""Writes vtk-scene.wrl with VTK's vtkVRMLExporter (a real exporter's VRML97: Viewpoint,
NavigationInfo, Background, an ambient DirectionalLight, a SpotLight, Transforms, Materials,
IndexedFaceSets with normals, re-DEF'd coordinate names).

    pip install vtk==9.7.2
    cd testdata/vrml && python3 make_vtk_scene.py

Off-screen rendering without an X server works (VTK prints a warning about the display).
"""
import vtk

ren = vtk.vtkRenderer()
win = vtk.vtkRenderWindow()
win.SetOffScreenRendering(1)
win.AddRenderer(ren)
win.SetSize(160, 120)


def actor(src, color, pos):
    m = vtk.vtkPolyDataMapper()
    m.SetInputConnection(src.GetOutputPort())
    a = vtk.vtkActor()
    a.SetMapper(m)
    a.GetProperty().SetColor(*color)
    a.SetPosition(*pos)
    ren.AddActor(a)


s = vtk.vtkSphereSource()
s.SetThetaResolution(16)
s.SetPhiResolution(8)
s.SetRadius(0.5)
actor(s, (0.8, 0.3, 0.2), (0, 0.5, 0))
p = vtk.vtkPlaneSource()
p.SetOrigin(-2, 0, -2)
p.SetPoint1(2, 0, -2)
p.SetPoint2(-2, 0, 2)
actor(p, (0.7, 0.7, 0.7), (0, 0, 0))
c = vtk.vtkCubeSource()
c.SetXLength(0.6)
c.SetYLength(0.6)
c.SetZLength(0.6)
actor(c, (0.2, 0.4, 0.8), (1.0, 0.3, 0.5))
light = vtk.vtkLight()
light.SetPosition(1, 3, 2)
light.SetFocalPoint(0, 0, 0)
light.SetPositional(1)
light.SetConeAngle(40)  # degrees; the exporter writes it as cutOffAngle 40 (VRML wants radians)
ren.AddLight(light)
cam = ren.GetActiveCamera()
cam.SetPosition(0, 2, 5)
cam.SetFocalPoint(0, 0.3, 0)
cam.SetViewUp(0, 1, 0)
win.Render()
e = vtk.vtkVRMLExporter()
e.SetRenderWindow(win)
e.SetFileName("vtk-scene.wrl")
e.Write()
