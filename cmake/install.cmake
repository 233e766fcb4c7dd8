# What `cmake --install` puts where, and the Debian package CPack makes of it (`cpack -G DEB` in
# the build folder). docs/architecture.md, "Installed", says where each file goes and how a
# program finds the shipped ones; README.md, "Installing for a lab", how to use the package.
#
#   bin/                              the lessons (01_ray_casting ...) and the tools a user runs
#   share/illumination-lessons/       scenes/ (with their meshes and maps), page/ (the studio's),
#                                     references/ (the converged references the studio uses)
#   share/doc/illumination-lessons/   README.md and docs/ (with its images)

# The lessons, under their own names.
install(TARGETS ${LESSONS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The tools a user needs, each under a name of its own: /usr/bin/compare is ImageMagick's and
# /usr/bin/merge RCS's. compare (error metrics and images), merge (the farm's parts), studio (the
# lessons live in a browser), scene_export (a scene as JSON, for the Blender bridge). The others
# (bench_bvh, sampler_strata, make_scene_maps) measure or make the suite itself and stay in the
# build tree.
# install(PROGRAMS) renames but, unlike install(TARGETS), does not strip: with --strip (and in
# the package, CPACK_STRIP_FILES) the renamed copies are stripped here, as the lessons are.
foreach(tool compare merge studio scene_export)
    string(REPLACE "_" "-" installed_name "illumination-${tool}")
    install(PROGRAMS $<TARGET_FILE:${tool}> DESTINATION ${CMAKE_INSTALL_BINDIR}
            RENAME ${installed_name})
    install(CODE "
        if(CMAKE_INSTALL_DO_STRIP)
            execute_process(COMMAND \"${CMAKE_STRIP}\"
                \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_BINDIR}/${installed_name}\")
        endif()")
endforeach()

# The shipped files (common/io/shipped_files.h): the scenes with the files they name, the page.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${LESSONS_INSTALL_SHIPPED}/scenes)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/tools/studio/page/
        DESTINATION ${LESSONS_INSTALL_SHIPPED}/page)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/references/
        DESTINATION ${LESSONS_INSTALL_SHIPPED}/references)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)

# The build tree has the install's layout: build/bin/ beside build/share/illumination-lessons/,
# whose folders are links to the source tree's, so that a program finds the shipped files the
# same way built and installed.
get_filename_component(build_shipped "${CMAKE_RUNTIME_OUTPUT_DIRECTORY}/${LESSONS_BIN_TO_SHIPPED}"
                       ABSOLUTE)
file(MAKE_DIRECTORY ${build_shipped})
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/scenes ${build_shipped}/scenes SYMBOLIC)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/tools/studio/page ${build_shipped}/page SYMBOLIC)
file(CREATE_LINK ${PROJECT_SOURCE_DIR}/references ${build_shipped}/references SYMBOLIC)

# The Debian package: illumination-lessons_VERSION_ARCH.deb, installing under /usr. Its
# dependencies are the shared libraries the programs link, found by dpkg-shlibdeps (dpkg-dev).
set(CPACK_PACKAGE_NAME ${LESSONS_PACKAGE})
set(CPACK_PACKAGE_VENDOR "Suite developers")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
string(CONCAT CPACK_PACKAGE_DESCRIPTION
    "Six programs render the same scenes with the illumination models of a lecture, in order: "
    "ray casting, Whitted recursion, the reflection equation, path tracing, bidirectional path "
    "tracing, photon mapping. With the scenes they render (share/illumination-lessons/scenes, "
    "found by name: 01_ray_casting --scene cornell_box), tools to compare and merge renders, and "
    "the studio, which shows the lessons converging live in a browser.")
set(CPACK_PACKAGE_CONTACT "Suite developers <dev@lessons.invalid>")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${CPACK_PACKAGE_CONTACT}")
set(CPACK_DEBIAN_PACKAGE_SECTION "graphics")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)
set(CPACK_GENERATOR DEB)
if(LESSONS_NATIVE)
    message(STATUS "package: built with -march=native, a .deb runs only on CPUs like this one "
                   "(-DLESSONS_NATIVE=OFF for a lab's mixed machines)")
endif()
include(CPack)
