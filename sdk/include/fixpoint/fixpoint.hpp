// Everything a plugin needs.
#pragma once

#include <fixpoint/batch.hpp>
#include <fixpoint/colourer.hpp>
#include <fixpoint/errors.hpp>
#include <fixpoint/filter.hpp>
#include <fixpoint/finish.hpp>
#include <fixpoint/frame.hpp>
#include <fixpoint/histogram.hpp>
#include <fixpoint/iteration.hpp>
#include <fixpoint/metric.hpp>
#include <fixpoint/number_system.hpp>
#include <fixpoint/object.hpp>
#include <fixpoint/params.hpp>
#include <fixpoint/plugin.hpp>
#include <fixpoint/render.hpp>
#include <fixpoint/rng.hpp>
#include <fixpoint/shape.hpp>
#include <fixpoint/shape_base.hpp>
#include <fixpoint/text.hpp>
#include <fixpoint/transform.hpp>
#include <fixpoint/transform_base.hpp>
#include <fixpoint/trap.hpp>
#include <fixpoint/types.hpp>
#include <fixpoint/vertex_map.hpp>
